//! The scenes by name, with numeric parameters by name: the one registry the command line and the Python module
//! use. Unknown names and parameters are errors naming them; counts must be whole numbers within limits, checked
//! before anything is allocated.

use super::{spinning_top, Cloth};
use crate::error::WorldError;
use crate::world::World;

/// The built-in scenes' names.
pub const NAMES: [&str; 20] = [
    "cloth",
    "spinning_top",
    "bouncing_ball",
    "tumbling_box",
    "dominoes",
    "pyramid",
    "pile",
    "cloth_drape",
    "pendulum",
    "chain",
    "newtons_cradle",
    "door",
    "ragdoll",
    "benchmark",
    "ball_in_cup",
    "ring_on_peg",
    "chair",
    "torus_roll",
    "mesh_pile",
    "wrecking_ball",
];

/// Largest count a scene parameter may take (particles a side, dominoes, pyramid layers).
const MAX_COUNT: f64 = 1000.0;

/// Named parameters, each taken at most once.
struct Params<'a> {
    given: &'a [(String, f64)],
    used: Vec<bool>,
}

impl<'a> Params<'a> {
    fn new(given: &'a [(String, f64)]) -> Self {
        Params { given, used: vec![false; given.len()] }
    }

    /// The number given for `key`, or `default`.
    fn number(&mut self, key: &'static str, default: f64) -> Result<f64, WorldError> {
        match self.given.iter().position(|(k, _)| k == key) {
            Some(i) => {
                self.used[i] = true;
                let v = self.given[i].1;
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(WorldError::invalid(key, format!("must be finite, got {v}")))
                }
            }
            None => Ok(default),
        }
    }

    /// The whole number given for `key` (1 ..= 1000), or `default`.
    fn count(&mut self, key: &'static str, default: usize) -> Result<usize, WorldError> {
        let v = self.number(key, default as f64)?;
        if v.fract() != 0.0 || !(1.0..=MAX_COUNT).contains(&v) {
            return Err(WorldError::invalid(key, format!("must be a whole number from 1 to {MAX_COUNT}, got {v}")));
        }
        Ok(v as usize)
    }

    /// A yes-or-no parameter given as 0 or 1, or `false` (the mesh scenes' only, which need contact).
    fn flag(&mut self, key: &'static str) -> Result<bool, WorldError> {
        match self.number(key, 0.0)? {
            0.0 => Ok(false),
            1.0 => Ok(true),
            v => Err(WorldError::invalid(key, format!("must be 0 or 1, got {v}"))),
        }
    }

    /// An error naming the first parameter the scene did not take.
    fn finish(&self, scene: &str) -> Result<(), WorldError> {
        match self.used.iter().position(|u| !u) {
            Some(i) => {
                Err(WorldError::invalid("params", format!("scene {scene:?} has no parameter {:?}", self.given[i].0)))
            }
            None => Ok(()),
        }
    }
}

/// The scene `name` built with `params` (each parameter's default where not given).
pub fn build(name: &str, params: &[(String, f64)]) -> Result<World, WorldError> {
    scene(name, params, true)?.ok_or_else(|| WorldError::invalid("name", "the scene was checked but not built"))
}

/// Checks the scene's name and parameters (by name, with their ranges) without building it: what a scene built
/// elsewhere (the Python module's cloth) calls first.
pub fn check(name: &str, params: &[(String, f64)]) -> Result<(), WorldError> {
    scene(name, params, false).map(|_| ())
}

/// Parses and checks the parameters, then builds the world if `make`.
fn scene(name: &str, params: &[(String, f64)], make: bool) -> Result<Option<World>, WorldError> {
    let mut p = Params::new(params);
    let world = match name {
        "cloth" => {
            let d = Cloth::default();
            let cloth = Cloth {
                n: p.count("n", d.n)?,
                size: p.number("size", d.size)?,
                mass: p.number("mass", d.mass)?,
                stiffness: p.number("stiffness", d.stiffness)?,
                damping: p.number("damping", d.damping)?,
                pin_stiffness: p.number("pin_stiffness", d.pin_stiffness)?,
            };
            p.finish(name)?;
            cloth.check()?;
            if make {
                Some(cloth.build()?.0)
            } else {
                None
            }
        }
        "spinning_top" => {
            p.finish(name)?;
            if make {
                Some(spinning_top()?.0)
            } else {
                None
            }
        }
        _ => return contact_scene(name, p, make),
    };
    Ok(world)
}

/// The jointed scenes (`joints.rs`).
fn jointed(name: &str, mut p: Params<'_>, make: bool) -> Result<Option<World>, WorldError> {
    use super::joints;
    let world = match name {
        "pendulum" => {
            let (length, radius) = (p.number("length", 1.0)?, p.number("radius", 0.05)?);
            p.finish(name)?;
            make.then(|| joints::pendulum(length, radius).map(|s| s.0)).transpose()?
        }
        "chain" => {
            let links = p.count("links", 20)?;
            p.finish(name)?;
            make.then(|| joints::chain(links).map(|s| s.0)).transpose()?
        }
        "newtons_cradle" => {
            let (balls, angle) = (p.count("balls", 5)?, p.number("angle", 0.5)?);
            p.finish(name)?;
            make.then(|| joints::newtons_cradle(balls, angle).map(|s| s.0)).transpose()?
        }
        "door" => {
            p.finish(name)?;
            make.then(|| joints::door().map(|s| s.0)).transpose()?
        }
        _ => {
            p.finish(name)?;
            make.then(|| joints::ragdoll().map(|s| s.0)).transpose()?
        }
    };
    Ok(world)
}

/// The mesh scenes (`meshes.rs`): `fast=1` runs fast mode at 1/240 s (accurate mode otherwise); `hull=1` gives
/// the cup, or the pile's meshes, their convex hulls.
fn mesh_scene(name: &str, mut p: Params<'_>, make: bool) -> Result<Option<World>, WorldError> {
    use super::meshes;
    let mode = if p.flag("fast")? { crate::mode::Mode::fast(1.0 / 240.0) } else { crate::mode::Mode::default() };
    let hull = if matches!(name, "ball_in_cup" | "mesh_pile") { p.flag("hull")? } else { false };
    let count = if name == "mesh_pile" { p.count("count", 50)? } else { 0 };
    p.finish(name)?;
    if !make {
        return Ok(None);
    }
    Ok(Some(match name {
        "ball_in_cup" => meshes::ball_in_cup(mode, hull)?.0,
        "ring_on_peg" => meshes::ring_on_peg(mode)?.0,
        "chair" => meshes::chair(mode)?.0,
        "torus_roll" => meshes::torus_roll(mode)?.0,
        _ => meshes::mesh_pile(mode, count, hull)?.0,
    }))
}

/// The wrecking ball (`fracture.rs`): `fast=1` runs fast mode at `dt` (1/240 s unless given; accurate mode
/// otherwise, which takes no `dt`), the glue's `strength` (Pa) and `window` (s).
fn wrecking_ball(mut p: Params<'_>, make: bool) -> Result<Option<World>, WorldError> {
    let fast = p.flag("fast")?;
    let given_dt = p.given.iter().any(|(k, _)| k == "dt");
    let dt = p.number("dt", 1.0 / 240.0)?;
    let d = super::WreckingBall::default();
    let scene =
        super::WreckingBall { strength: p.number("strength", d.strength)?, window: p.number("window", d.window)? };
    p.finish("wrecking_ball")?;
    if given_dt && !fast {
        return Err(WorldError::invalid("dt", "accurate mode chooses its own steps; dt is fast mode's"));
    }
    let mode = if fast { crate::mode::Mode::fast(dt) } else { crate::mode::Mode::default() };
    if !make {
        return Ok(None);
    }
    Ok(Some(scene.build(mode)?.0))
}

fn unknown(name: &str) -> WorldError {
    WorldError::invalid("name", format!("unknown scene {name:?}; expected one of {}", NAMES.join(", ")))
}

fn contact_scene(name: &str, mut p: Params<'_>, make: bool) -> Result<Option<World>, WorldError> {
    use super::{tumbling_box, BouncingBall, ClothDrape, Dominoes, Pile, Pyramid};
    let world = match name {
        "bouncing_ball" => {
            let d = BouncingBall::default();
            let ball = BouncingBall {
                restitution: p.number("restitution", d.restitution)?,
                radius: p.number("radius", d.radius)?,
                height: p.number("height", d.height)?,
            };
            p.finish(name)?;
            ball.check()?;
            if make {
                Some(ball.build()?.0)
            } else {
                None
            }
        }
        "tumbling_box" => {
            p.finish(name)?;
            if make {
                Some(tumbling_box()?.0)
            } else {
                None
            }
        }
        "dominoes" => {
            let d = Dominoes::default();
            let row = Dominoes { count: p.count("count", d.count)?, spacing: p.number("spacing", d.spacing)? };
            p.finish(name)?;
            row.check()?;
            if make {
                Some(row.build()?.0)
            } else {
                None
            }
        }
        "pyramid" => {
            let pyramid = Pyramid { layers: p.count("layers", Pyramid::default().layers)? };
            p.finish(name)?;
            pyramid.check()?;
            if make {
                Some(pyramid.build()?.0)
            } else {
                None
            }
        }
        "pile" => {
            let d = Pile::default();
            let pile = Pile { side: p.count("side", d.side)?, layers: p.count("layers", d.layers)? };
            p.finish(name)?;
            pile.check()?;
            if make {
                Some(pile.build()?.0)
            } else {
                None
            }
        }
        "cloth_drape" => {
            let d = ClothDrape::default();
            let drape = ClothDrape { n: p.count("n", d.n)?, size: p.number("size", d.size)? };
            p.finish(name)?;
            drape.check()?;
            if make {
                Some(drape.build()?.0)
            } else {
                None
            }
        }
        "ball_in_cup" | "ring_on_peg" | "chair" | "torus_roll" | "mesh_pile" => return mesh_scene(name, p, make),
        "benchmark" => {
            // the scenes accurate mode is compared with CENIC on (`benchmark.rs`), by number
            use super::Benchmark;
            let which = p.count("which", 1)?;
            let degrees = p.number("degrees", 35.0)?;
            p.finish(name)?;
            let scene = match which {
                1 => Benchmark::Slide,
                2 => Benchmark::Incline { degrees },
                3 => Benchmark::Roll,
                4 => Benchmark::CubePile,
                5 => Benchmark::DominoRow,
                other => {
                    return Err(WorldError::invalid(
                        "which",
                        format!("1 slide, 2 incline, 3 roll, 4 cube pile, 5 domino row; got {other}"),
                    ))
                }
            };
            if !(0.0..90.0).contains(&degrees) {
                return Err(WorldError::invalid("degrees", format!("must be in [0, 90), got {degrees}")));
            }
            make.then(|| scene.build().map(|s| s.0)).transpose()?
        }
        "pendulum" | "chain" | "newtons_cradle" | "door" | "ragdoll" => return jointed(name, p, make),
        "wrecking_ball" => return wrecking_ball(p, make),
        other => return Err(unknown(other)),
    };
    Ok(world)
}
