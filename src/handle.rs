//! Typed generational handles and the arena that hands them out: a handle stays valid until its object is
//! removed, and a removed slot's new occupant gets a new generation, so a stale handle is caught, never aliased.
//! Each world numbers itself (a process-wide counter), and its handles carry that number, so a handle from another
//! world is caught too.

use std::fmt;
use std::marker::PhantomData;

/// A handle to an object of type `T` in a world.
pub struct Handle<T> {
    world: u64,
    index: u32,
    generation: u32,
    _type: PhantomData<fn() -> T>,
}

impl<T> Handle<T> {
    /// The slot index (stable while the object lives).
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The generation of the slot when the handle was issued.
    pub fn generation(&self) -> u32 {
        self.generation
    }

    /// The number of the world that issued it.
    pub fn world(&self) -> u64 {
        self.world
    }

    /// Rebuilds a handle from its parts (for bindings that pass handles through other languages).
    pub fn from_world_parts(world: u64, index: u32, generation: u32) -> Self {
        Handle { world, index, generation, _type: PhantomData }
    }

    /// A handle of no world (world number 0, which no world has) with this index and generation: every world
    /// refuses it.
    pub fn from_parts(index: u32, generation: u32) -> Self {
        Handle::from_world_parts(0, index, generation)
    }
}

impl<T> Clone for Handle<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Handle<T> {}
impl<T> PartialEq for Handle<T> {
    fn eq(&self, o: &Self) -> bool {
        self.world == o.world && self.index == o.index && self.generation == o.generation
    }
}
impl<T> Eq for Handle<T> {}
impl<T> std::hash::Hash for Handle<T> {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        (self.world, self.index, self.generation).hash(state)
    }
}
impl<T> fmt::Debug for Handle<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // `Handle<RigidBody>` is `BodyHandle` in both APIs
        let name = std::any::type_name::<T>().rsplit("::").next().unwrap_or("Object").trim_start_matches("Rigid");
        write!(f, "{name}Handle({}v{})", self.index, self.generation)
    }
}

#[derive(Clone)]
struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

/// Objects in slots, iterated in slot order (which is the order of the state vector).
#[derive(Clone)]
pub(crate) struct Arena<T> {
    world: u64,
    slots: Vec<Slot<T>>,
    free: Vec<u32>,
    len: usize,
}

/// A number no other world of this process has.
pub(crate) fn new_world_number() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl<T> Arena<T> {
    /// An empty arena of world number `world`.
    pub fn new(world: u64) -> Self {
        Arena { world, slots: Vec::new(), free: Vec::new(), len: 0 }
    }

    pub fn insert(&mut self, value: T) -> Handle<T> {
        self.len += 1;
        if let Some(index) = self.free.pop() {
            let slot = &mut self.slots[index as usize];
            slot.value = Some(value);
            return Handle::from_world_parts(self.world, index, slot.generation);
        }
        self.slots.push(Slot { generation: 0, value: Some(value) });
        Handle::from_world_parts(self.world, self.slots.len() as u32 - 1, 0)
    }

    pub fn get(&self, h: Handle<T>) -> Option<&T> {
        if h.world != self.world {
            return None;
        }
        self.slots.get(h.index as usize).filter(|s| s.generation == h.generation).and_then(|s| s.value.as_ref())
    }

    pub fn get_mut(&mut self, h: Handle<T>) -> Option<&mut T> {
        if h.world != self.world {
            return None;
        }
        self.slots.get_mut(h.index as usize).filter(|s| s.generation == h.generation).and_then(|s| s.value.as_mut())
    }

    pub fn remove(&mut self, h: Handle<T>) -> Option<T> {
        if h.world != self.world {
            return None;
        }
        let slot = self.slots.get_mut(h.index as usize).filter(|s| s.generation == h.generation)?;
        let value = slot.value.take()?;
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(h.index);
        self.len -= 1;
        Some(value)
    }

    pub fn len(&self) -> usize {
        self.len
    }

    /// Live objects in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (Handle<T>, &T)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            s.value.as_ref().map(|v| (Handle::from_world_parts(self.world, i as u32, s.generation), v))
        })
    }

    /// Live objects in slot order, mutable.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = (Handle<T>, &mut T)> {
        let world = self.world;
        self.slots.iter_mut().enumerate().filter_map(move |(i, s)| {
            let generation = s.generation;
            s.value.as_mut().map(|v| (Handle::from_world_parts(world, i as u32, generation), v))
        })
    }

    /// A live object's row: its place among the live objects in slot order.
    pub fn row(&self, h: Handle<T>) -> Option<usize> {
        self.get(h)?;
        Some(self.slots[..h.index as usize].iter().filter(|s| s.value.is_some()).count())
    }

    pub fn retain(&mut self, mut keep: impl FnMut(&T) -> bool) {
        let doomed: Vec<Handle<T>> = self.iter().filter(|(_, v)| !keep(v)).map(|(h, _)| h).collect();
        for h in doomed {
            self.remove(h);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_handles_are_caught_after_reuse() {
        let mut a: Arena<&str> = Arena::new(1);
        let x = a.insert("x");
        let y = a.insert("y");
        assert_eq!(a.remove(x), Some("x"));
        let z = a.insert("z");
        assert_eq!(z.index(), x.index(), "the freed slot is reused");
        assert_eq!(a.get(x), None, "the old handle is stale");
        assert_eq!(a.get(z), Some(&"z"));
        assert_eq!(a.iter().map(|(_, v)| *v).collect::<Vec<_>>(), vec!["z", "y"]);
        assert_eq!(a.len(), 2);
        assert_eq!(a.get(y), Some(&"y"));
    }
}
