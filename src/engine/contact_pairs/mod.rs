//! Fast mode's contact pairs kept across steps: each collider pair that touched keeps, from one step to the next,
//! its manifold in its bodies' frames, which of its points the reduction chose, and its contacts as the soft step
//! solves them (`SoftManifold`: the points, their impulses, which start the next step, and the pair's colour in the
//! constraint graph, taken when the pair begins to touch and given back when it ends), in one list sorted by pair
//! that a step's search walks forward (the broad phase gives the pairs sorted): no map of keys, no sort.

mod pair;

pub(crate) use pair::Pair;

use crate::engine::last_contacts::LastContact;
use tumble_contact::{BodyState, ColourGraph, SoftManifold, UNCOLOURED};

/// The pairs kept across steps, sorted by pair, and the colours their contacts hold in the constraint graph (a
/// function of the pairs' colours, rebuilt from them where a memory is given back, `rebuild`).
#[derive(serde::Serialize, serde::Deserialize, Debug, Default)]
pub(crate) struct ContactPairs {
    pairs: Vec<Pair>,
    /// The pairs of bodies asleep (or asleep on static ones), sorted: kept as they were, not searched or solved, so
    /// that an island woken finds its contacts with their impulses (a woken pile started from none sags).
    resting: Vec<Pair>,
    #[serde(skip)]
    graph: ColourGraph,
}

impl Clone for ContactPairs {
    fn clone(&self) -> Self {
        ContactPairs { pairs: self.pairs.clone(), resting: self.resting.clone(), graph: self.graph.clone() }
    }

    fn clone_from(&mut self, o: &Self) {
        self.pairs.clone_from(&o.pairs);
        self.resting.clone_from(&o.resting);
        self.graph.clone_from(&o.graph);
    }
}

impl ContactPairs {
    /// The last step's entries of `pairs` (sorted), moved out, a fresh one for a pair new this step (a resting one
    /// back if its bodies woke); of the rest (their boxes no longer overlap, or their bodies sleep), those that
    /// `rest` says sleep are kept resting, the others dropped, their colours given back (`moves` says which actors
    /// take colours: those a sweep moves). `close` puts them back. A step whose pairs are the last step's, with
    /// nothing resting woken, takes them as they are.
    pub fn open(
        &mut self,
        pairs: &[(usize, usize)],
        moves: impl Fn(usize) -> bool,
        rest: impl Fn((usize, usize)) -> bool,
    ) -> Vec<Pair> {
        if self.resting.iter().any(|p| !rest(p.pair())) {
            let (woken, resting): (Vec<Pair>, Vec<Pair>) =
                std::mem::take(&mut self.resting).into_iter().partition(|p| !rest(p.pair()));
            self.resting = resting;
            self.pairs = merged(std::mem::take(&mut self.pairs), woken);
        }
        if self.pairs.len() == pairs.len() && self.pairs.iter().zip(pairs).all(|(p, &q)| p.pair() == q) {
            return std::mem::take(&mut self.pairs);
        }
        let mut kept = std::mem::take(&mut self.pairs).into_iter().peekable();
        let (graph, mut asleep) = (&mut self.graph, Vec::new());
        let mut leave = |p: Pair| {
            if rest(p.pair()) && !p.contacts.is_empty() {
                asleep.push(p);
            } else {
                for m in &p.contacts {
                    graph.remove(m.colour, (m.a, moves(m.a)), (m.b, moves(m.b)));
                }
            }
        };
        let mut out: Vec<Pair> = pairs
            .iter()
            .map(|&pair| {
                while let Some(gone) = kept.next_if(|p| p.pair() < pair) {
                    leave(gone);
                }
                kept.next_if(|p| p.pair() == pair).unwrap_or_else(|| Pair::new(pair))
            })
            .collect();
        kept.for_each(leave);
        if !asleep.is_empty() {
            self.resting = merged(std::mem::take(&mut self.resting), asleep);
        }
        out.shrink_to_fit();
        out
    }

    /// Ends a step's search: its pairs (as `open` gave them, in order) become the ones kept, those with neither
    /// contacts nor a manifold dropped; a pair whose contacts ended gives back its colour, and one whose contacts
    /// began takes one, in pair order (`actors` says how many actors the graph has, `moves` which take colours).
    pub fn close(&mut self, mut pairs: Vec<Pair>, actors: usize, moves: impl Fn(usize) -> bool) {
        if self.graph.len() != actors {
            self.graph = ColourGraph::new(actors);
        }
        for m in pairs.iter_mut().flat_map(|p| p.contacts.iter_mut()) {
            if m.count == 0 && m.colour != UNCOLOURED {
                self.graph.remove(m.colour, (m.a, moves(m.a)), (m.b, moves(m.b)));
                m.colour = UNCOLOURED;
            }
        }
        for p in pairs.iter_mut() {
            p.contacts.retain(|m| m.count > 0);
            for m in p.contacts.iter_mut() {
                if m.colour == UNCOLOURED {
                    m.colour = self.graph.add((m.a, moves(m.a)), (m.b, moves(m.b)));
                }
            }
        }
        pairs.retain(|p| p.has_manifold() || !p.contacts.is_empty());
        self.pairs = pairs;
    }

    /// The graph of `actors` actors rebuilt from the pairs' colours (`moves` says which actors take them): after a
    /// memory is given back. An error if two pairs of one colour share an actor that moves.
    pub fn rebuild(&mut self, actors: usize, moves: impl Fn(usize) -> bool) -> Result<(), String> {
        let mut graph = ColourGraph::new(actors);
        for m in self.pairs.iter().chain(&self.resting).flat_map(|p| &p.contacts) {
            if m.colour == UNCOLOURED {
                continue;
            }
            let (a, b) = ((m.a, moves(m.a)), (m.b, moves(m.b)));
            if m.a >= actors || m.b >= actors || !graph.fits(m.colour, a, b) {
                return Err("two of its contact pairs of one colour share a body".into());
            }
            graph.take(m.colour, a, b);
        }
        self.graph = graph;
        Ok(())
    }

    /// The contacts the soft step solves: every pair's that has points and a body that moves in `states` (the step's
    /// actors, sleeping ones fixed).
    pub fn manifolds<'a>(&'a mut self, states: &[BodyState]) -> Vec<&'a mut SoftManifold> {
        let moving = |m: &SoftManifold| states[m.a].is_dynamic() || states[m.b].is_dynamic();
        self.pairs.iter_mut().flat_map(|p| p.contacts.iter_mut()).filter(|m| m.count > 0 && moving(m)).collect()
    }

    /// The actor pairs of every pair with contacts, resting ones too.
    pub fn touching(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.pairs.iter().chain(&self.resting).filter_map(|p| p.contacts.first()).map(|m| (m.a, m.b))
    }

    /// The deepest overlap among the contacts (0 if none overlaps).
    pub fn penetration(&self) -> f64 {
        self.pairs.iter().flat_map(|p| &p.contacts).flat_map(|m| m.points()).map(|c| -c.gap).fold(0.0, f64::max)
    }

    /// The last step's contacts (a step of `step` s), with their impulses over it.
    pub fn last_contacts(&self, step: f64) -> Vec<LastContact> {
        let mut out = Vec::new();
        for m in self.pairs.iter().flat_map(|p| &p.contacts) {
            out.extend(m.points().iter().map(|c| LastContact {
                a: m.a,
                b: m.b,
                point: c.point,
                normal: c.normal,
                gap: c.gap,
                impulse: c.step_normal,
                step,
            }));
        }
        out
    }

    /// Whether it fits a scene of `colliders` colliders: pairs in range and sorted, every kept choice within its
    /// manifold, impulses in order.
    pub fn fits(&self, colliders: usize) -> bool {
        let fits = |pairs: &[Pair]| {
            pairs.iter().all(|p| p.fits(colliders)) && pairs.windows(2).all(|w| w[0].pair() < w[1].pair())
        };
        fits(&self.pairs) && fits(&self.resting)
    }

    /// Contact points kept, in all.
    #[cfg(test)]
    pub fn kept_points(&self) -> usize {
        self.pairs.iter().chain(&self.resting).flat_map(|p| &p.contacts).map(|m| m.count).sum()
    }
}

/// Two lists of pairs sorted by pair (and sharing none) merged into one.
fn merged(a: Vec<Pair>, b: Vec<Pair>) -> Vec<Pair> {
    if b.is_empty() {
        return a;
    }
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut a, mut b) = (a.into_iter().peekable(), b.into_iter().peekable());
    loop {
        let next = match (a.peek(), b.peek()) {
            (Some(x), Some(y)) => {
                if x.pair() < y.pair() {
                    a.next()
                } else {
                    b.next()
                }
            }
            (Some(_), None) => a.next(),
            (None, _) => b.next(),
        };
        match next {
            Some(p) => out.push(p),
            None => return out,
        }
    }
}
