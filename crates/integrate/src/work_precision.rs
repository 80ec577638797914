//! Work-precision measurement.
