//! The driver's side of an integration's memory (`memory.rs`): the integrator's state and the method's written out
//! as plain data, and read back into an integrator of the same system and settings.

use super::Integrator;
use crate::error::OdeError;
use crate::memory::{IntegratorMemory, Item, MemoryReader, MemoryWriter};
use crate::system::OdeSystem;

impl<S: OdeSystem + ?Sized> Integrator<S> {
    /// The integration's memory as plain data: the current and next points, the step sizes, the controller's
    /// history and the method's stages, histories and Jacobian. Given back with
    /// [`set_memory`](Integrator::set_memory) to an integrator of the same system and settings, it continues bit
    /// for bit as this one would (the report and the step log are not part of it).
    pub fn memory(&self) -> IntegratorMemory {
        let mut out = MemoryWriter { items: Vec::new() };
        out.point(&self.cur);
        out.point(&self.next);
        out.maybe(self.h);
        out.maybe(self.last_step);
        out.flag(self.last_rejected);
        out.numbers(&self.dense_buf);
        out.numbers(&self.backup);
        self.controller.save(&mut out);
        self.stepper.save(&mut out);
        IntegratorMemory { method: self.settings.method.name().to_string(), items: out.items }
    }

    /// Gives back a memory taken by [`memory`](Integrator::memory) from an integrator of the same system and
    /// settings. A memory of another method or size is an error naming `memory`, and the integrator is unchanged.
    pub fn set_memory(&mut self, memory: &IntegratorMemory) -> Result<(), OdeError> {
        let name = self.settings.method.name();
        if memory.method != name {
            return Err(OdeError::invalid("memory", format!("is {}'s, this integrator runs {name}", memory.method)));
        }
        let mut copy = self.clone();
        copy.read_memory(memory.items.clone()).map_err(|why| OdeError::invalid("memory", why))?;
        *self = copy;
        Ok(())
    }

    fn read_memory(&mut self, items: Vec<Item>) -> Result<(), String> {
        let mut input = MemoryReader::new(items);
        input.point("current point", &mut self.cur)?;
        input.point("next point", &mut self.next)?;
        self.h = input.maybe("proposed step")?;
        self.last_step = input.maybe("last step")?;
        for (name, h) in [("proposed step", self.h), ("last step", self.last_step)] {
            // (an unbounded tolerance lets the controller propose an infinite step: the step limits cap it)
            if h.is_some_and(|h| !(h > 0.0)) {
                return Err(format!("`{name}` must be positive"));
            }
        }
        if !self.cur.t.is_finite() {
            return Err("`current point` has a time that is not finite".into());
        }
        self.last_rejected = input.flag("last rejected")?;
        input.numbers("dense output", &mut self.dense_buf)?;
        input.numbers("backup", &mut self.backup)?;
        self.controller.load(&mut input)?;
        self.stepper.load(&mut input)?;
        input.finish()
    }
}
