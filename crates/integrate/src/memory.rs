//! An integration's memory as plain data: what the driver and the method keep between steps (the current and next
//! points, step sizes, the controller's history, the method's stages, histories and Jacobian), written in a fixed
//! order so that it can be saved and given back to an integrator of the same system and settings, which then
//! continues bit for bit. Factorizations are not kept: they are rebuilt from the saved Jacobian when next needed,
//! to the same bits. Point ids are kept as they were (caches compare ids only within one integrator, as in a copy).
//! The driver takes and gives back its memory in `integrator/memory.rs`.

use crate::point::{Point, NEXT_SLOT, SLOT_SHIFT};
use std::sync::atomic::Ordering;

/// One value of a memory.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) enum Item {
    Numbers(Vec<f64>),
    Number(f64),
    Maybe(Option<f64>),
    Flag(bool),
    Count(u64),
    Id(Option<u64>),
}

impl Item {
    fn kind(&self) -> &'static str {
        match self {
            Item::Numbers(_) => "numbers",
            Item::Number(_) => "a number",
            Item::Maybe(_) => "an optional number",
            Item::Flag(_) => "a flag",
            Item::Count(_) => "a count",
            Item::Id(_) => "a point id",
        }
    }
}

/// An integrator's memory ([`Integrator::memory`](crate::Integrator::memory)): the method's name and its values in
/// the order the driver and the method write them. Opaque; with the `serde` feature it serializes.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct IntegratorMemory {
    pub(crate) method: String,
    pub(crate) items: Vec<Item>,
}

impl IntegratorMemory {
    /// The name of the method whose memory this is.
    pub fn method(&self) -> &str {
        &self.method
    }
}

/// Writes a memory's values in order.
pub(crate) struct MemoryWriter {
    pub items: Vec<Item>,
}

impl MemoryWriter {
    pub fn numbers(&mut self, v: &[f64]) {
        self.items.push(Item::Numbers(v.to_vec()));
    }

    pub fn number(&mut self, x: f64) {
        self.items.push(Item::Number(x));
    }

    pub fn maybe(&mut self, x: Option<f64>) {
        self.items.push(Item::Maybe(x));
    }

    pub fn flag(&mut self, b: bool) {
        self.items.push(Item::Flag(b));
    }

    pub fn count(&mut self, n: u64) {
        self.items.push(Item::Count(n));
    }

    pub fn id(&mut self, id: Option<u64>) {
        self.items.push(Item::Id(id));
    }

    /// A point: time, state, derivative (and whether it is evaluated), id.
    pub fn point(&mut self, p: &Point) {
        self.number(p.t);
        self.numbers(&p.y);
        self.numbers(&p.f);
        self.flag(p.has_f);
        self.id(Some(p.id));
    }
}

/// The error of a value of another kind than expected.
fn wrong(name: &str, expected: &str, found: &Item) -> String {
    format!("`{name}` should be {expected}, found {}", found.kind())
}

/// Reads a memory's values back in the order they were written, each checked for its kind and length; an error
/// names the value.
pub(crate) struct MemoryReader {
    items: std::vec::IntoIter<Item>,
    /// The largest point slot read, so that points made later never share one.
    max_slot: u64,
}

impl MemoryReader {
    pub fn new(items: Vec<Item>) -> Self {
        MemoryReader { items: items.into_iter(), max_slot: 0 }
    }

    fn next(&mut self, name: &str) -> Result<Item, String> {
        self.items.next().ok_or_else(|| format!("`{name}` is missing (the memory ends early)"))
    }

    /// Numbers into `into`, which they must fit exactly.
    pub fn numbers(&mut self, name: &str, into: &mut [f64]) -> Result<(), String> {
        match self.next(name)? {
            Item::Numbers(v) if v.len() == into.len() => {
                into.copy_from_slice(&v);
                Ok(())
            }
            Item::Numbers(v) => {
                Err(format!("`{name}` has {} numbers where this integration has {}", v.len(), into.len()))
            }
            other => Err(wrong(name, "numbers", &other)),
        }
    }

    pub fn number(&mut self, name: &str) -> Result<f64, String> {
        match self.next(name)? {
            Item::Number(x) => Ok(x),
            other => Err(wrong(name, "a number", &other)),
        }
    }

    pub fn maybe(&mut self, name: &str) -> Result<Option<f64>, String> {
        match self.next(name)? {
            Item::Maybe(x) => Ok(x),
            other => Err(wrong(name, "an optional number", &other)),
        }
    }

    pub fn flag(&mut self, name: &str) -> Result<bool, String> {
        match self.next(name)? {
            Item::Flag(b) => Ok(b),
            other => Err(wrong(name, "a flag", &other)),
        }
    }

    pub fn count(&mut self, name: &str) -> Result<u64, String> {
        match self.next(name)? {
            Item::Count(n) => Ok(n),
            other => Err(wrong(name, "a count", &other)),
        }
    }

    pub fn id(&mut self, name: &str) -> Result<Option<u64>, String> {
        let id = match self.next(name)? {
            Item::Id(id) => id,
            other => return Err(wrong(name, "a point id", &other)),
        };
        if let Some(id) = id {
            self.max_slot = self.max_slot.max(id >> SLOT_SHIFT);
        }
        Ok(id)
    }

    pub fn point(&mut self, name: &str, p: &mut Point) -> Result<(), String> {
        p.t = self.number(name)?;
        self.numbers(name, &mut p.y)?;
        self.numbers(name, &mut p.f)?;
        p.has_f = self.flag(name)?;
        p.id = self.id(name)?.ok_or_else(|| format!("`{name}` has no id"))?;
        Ok(())
    }

    /// Checks that nothing is left, and moves the process's next point slot past the ones read.
    pub fn finish(mut self) -> Result<(), String> {
        if let Some(extra) = self.items.next() {
            return Err(format!("{} left over after the last value", extra.kind()));
        }
        NEXT_SLOT.fetch_max(self.max_slot + 1, Ordering::Relaxed);
        Ok(())
    }
}
