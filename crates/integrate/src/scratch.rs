//! Scratch memory for faer's factorizations that can be cloned: a clone gets fresh memory of the same size (the
//! contents are workspace, never state), so an integrator can be copied whole.

use faer::dyn_stack::{MemBuffer, StackReq};
use std::ops::{Deref, DerefMut};

/// A `MemBuffer` that remembers its size.
pub(crate) struct Scratch {
    buf: MemBuffer,
    req: StackReq,
}

impl Scratch {
    pub fn new(req: StackReq) -> Self {
        Scratch { buf: MemBuffer::new(req), req }
    }
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Scratch::new(self.req)
    }
}

impl Deref for Scratch {
    type Target = MemBuffer;
    fn deref(&self) -> &MemBuffer {
        &self.buf
    }
}

impl DerefMut for Scratch {
    fn deref_mut(&mut self) -> &mut MemBuffer {
        &mut self.buf
    }
}
