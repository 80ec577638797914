//! What accurate mode's free flight (`free_flight.rs`) carries from step to step, part of the touching phase's
//! memory: the integration of the actors that touch nothing, with the components it holds still.

use super::integration::Integration;

/// The integration of the free actors, kept from step to step while the same actors are held (its proposed step
/// carries over).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct FreeFlight {
    /// The state components held still (those of the touching actors).
    #[serde(rename = "frozen")] // (its name in files)
    pub held_components: Vec<usize>,
    pub integration: Integration,
}
