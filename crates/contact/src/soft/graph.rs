//! The constraint graph's colours, kept from step to step (Box2D v3's `constraint_graph.c`): a manifold takes a
//! colour when it begins (the lowest that neither of its moving bodies has), keeps it while it lasts and gives it back
//! when it ends, so that an unchanged contact is never coloured again. Manifolds of one colour share no moving body:
//! they are solved side by side, in vector lanes and on threads, with the bits of one after another. A manifold that
//! finds every colour taken goes to the overflow colour, whose manifolds may share bodies and are solved one after
//! another. The colours depend on the order manifolds begin and end in, never on threads or timing.

/// Colours tracked per body; manifolds that find all of them taken get `OVERFLOW`.
pub const COLOURS: u32 = 64;

/// The colour of manifolds that may share a body (solved one after another, on one worker).
pub const OVERFLOW: u32 = COLOURS;

/// No colour: a manifold that has not begun (or has ended).
pub const UNCOLOURED: u32 = u32::MAX;

/// Each body's colours in use, a bit each.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default, PartialEq, Eq)]
pub struct ColourGraph {
    taken: Vec<u64>,
}

impl ColourGraph {
    /// A graph of `bodies` bodies, no colour taken.
    pub fn new(bodies: usize) -> ColourGraph {
        ColourGraph { taken: vec![0; bodies] }
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.taken.len()
    }

    /// Whether it has no bodies.
    pub fn is_empty(&self) -> bool {
        self.taken.is_empty()
    }

    /// Whether nothing is coloured.
    pub fn is_clear(&self) -> bool {
        self.taken.iter().all(|&t| t == 0)
    }

    /// The colour for a manifold beginning between bodies `a` and `b`, each taking part if it moves (a static or
    /// kinematic body, never written by a sweep, may be shared by any number of manifolds of a colour).
    pub fn add(&mut self, (a, a_moves): (usize, bool), (b, b_moves): (usize, bool)) -> u32 {
        let used = (if a_moves { self.taken[a] } else { 0 }) | (if b_moves { self.taken[b] } else { 0 });
        let colour = (!used).trailing_zeros();
        if colour >= COLOURS {
            return OVERFLOW;
        }
        for (body, moves) in [(a, a_moves), (b, b_moves)] {
            if moves {
                self.taken[body] |= 1 << colour;
            }
        }
        colour
    }

    /// Gives back the colour of a manifold ending between `a` and `b` (as `add` took it; the overflow colour and no
    /// colour take nothing).
    pub fn remove(&mut self, colour: u32, (a, a_moves): (usize, bool), (b, b_moves): (usize, bool)) {
        if colour >= COLOURS {
            return;
        }
        for (body, moves) in [(a, a_moves), (b, b_moves)] {
            if moves {
                self.taken[body] &= !(1 << colour);
            }
        }
    }

    /// Whether colour `colour` is free for a manifold between `a` and `b` (the overflow colour always is).
    pub fn fits(&self, colour: u32, (a, a_moves): (usize, bool), (b, b_moves): (usize, bool)) -> bool {
        colour == OVERFLOW
            || (colour < COLOURS
                && !(a_moves && self.taken[a] & (1 << colour) != 0)
                && !(b_moves && self.taken[b] & (1 << colour) != 0))
    }

    /// Takes colour `colour` for a manifold between `a` and `b` (which `fits` said is free): a kept manifold put
    /// back into a graph rebuilt from its colours.
    pub fn take(&mut self, colour: u32, (a, a_moves): (usize, bool), (b, b_moves): (usize, bool)) {
        if colour >= COLOURS {
            return;
        }
        for (body, moves) in [(a, a_moves), (b, b_moves)] {
            if moves {
                self.taken[body] |= 1 << colour;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifolds_of_a_colour_share_no_moving_body_and_colours_come_back() {
        // A chain of bodies 0-1-2-3 joined by manifolds, and every one on a static body 4: neighbours differ,
        // the static body is shared by any number of a colour, and a colour given back is the next one taken.
        let mut g = ColourGraph::new(5);
        let m = |i: usize| (i, i != 4);
        let c01 = g.add(m(0), m(1));
        let c12 = g.add(m(1), m(2));
        let c23 = g.add(m(2), m(3));
        assert_eq!((c01, c12, c23), (0, 1, 0));
        let grounds: Vec<u32> = (0..4).map(|i| g.add(m(i), m(4))).collect();
        assert_eq!(grounds, vec![1, 2, 2, 1]);
        // bodies 1 and 2 hold colours 0 and 2 besides the manifold's 1: given back, 1 is the lowest free again, and
        // the ground manifolds' colours stay taken
        g.remove(c12, m(1), m(2));
        assert!(g.fits(1, m(1), m(2)) && !g.fits(2, m(1), m(2)) && !g.fits(0, m(1), m(2)));
        assert_eq!(g.add(m(1), m(2)), 1);
        // 64 manifolds on one body fill its colours; the 65th overflows, and giving one back frees it
        let mut g = ColourGraph::new(70);
        let colours: Vec<u32> = (1..=65).map(|i| g.add((0, true), (i, true))).collect();
        assert_eq!(colours[63], 63);
        assert_eq!(colours[64], OVERFLOW);
        g.remove(5, (0, true), (6, true));
        assert_eq!(g.add((0, true), (66, true)), 5);
        g.remove(OVERFLOW, (0, true), (65, true));
        assert!(!g.is_clear());
    }
}
