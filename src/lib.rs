pub use tumble_integrate as integrate;
