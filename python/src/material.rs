//! Surface keywords as the bindings take them (`friction=`, `restitution=`, `rolling_resistance=`,
//! `torsional_resistance=`, `friction_combine=`, `restitution_combine=`), turned into the root crate's
//! `MaterialChange` in one place.

use crate::convert::world_error;
use pyo3::prelude::*;
use tumble::{Combine, Material, MaterialChange};

/// A surface's keywords (`None`: not given).
#[derive(Default)]
pub(crate) struct MaterialArgs {
    pub friction: Option<f64>,
    pub restitution: Option<f64>,
    pub rolling_resistance: Option<f64>,
    pub torsional_resistance: Option<f64>,
    pub friction_combine: Option<String>,
    pub restitution_combine: Option<String>,
}

/// A combine rule by name; "world" is the world's rule again.
fn rule(argument: &'static str, name: &Option<String>) -> PyResult<Option<Option<Combine>>> {
    name.as_deref()
        .map(|n| if n == "world" { Ok(None) } else { Combine::parse(argument, n).map(Some) })
        .transpose()
        .map_err(world_error)
}

impl MaterialArgs {
    /// The change the keywords ask for.
    pub fn change(&self) -> PyResult<MaterialChange> {
        Ok(MaterialChange {
            friction: self.friction,
            restitution: self.restitution,
            rolling_resistance: self.rolling_resistance,
            torsional_resistance: self.torsional_resistance,
            friction_combine: rule("friction_combine", &self.friction_combine)?,
            restitution_combine: rule("restitution_combine", &self.restitution_combine)?,
        })
    }

    /// The material of a new particle or body: the library's default with the keywords given.
    pub fn material(&self) -> PyResult<Material> {
        Ok(self.change()?.applied_to(Material::default()))
    }
}
