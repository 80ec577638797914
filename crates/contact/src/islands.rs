//! Islands: bodies that touch, directly or through other moving bodies, found by union-find over the contact graph.
//! Static bodies do not join islands (a floor under two separate boxes does not couple them).

use crate::body::BodyState;
use crate::contact::Contact;
use crate::union_find::UnionFind;

/// The contacts grouped by island: each inner list holds the indices of the contacts of one island, in their
/// original order; islands come in the order of their first contact.
pub fn islands(bodies: &[BodyState], contacts: &[Contact]) -> Vec<Vec<usize>> {
    let (of_link, count) = link_islands(bodies.len(), |b| bodies[b].is_dynamic(), contacts.iter().map(|c| (c.a, c.b)));
    let mut out = vec![Vec::new(); count];
    for (i, &k) in of_link.iter().enumerate() {
        out[k].push(i);
    }
    out
}

/// Islands of contacts and joints: bodies joined by a joint, or by a contact that `links`, are one island. Each
/// island lists its contacts and its joints (`pairs`, the joints' bodies), each in their original order; islands
/// come in the order of their first contact, then of their first joint. A contact that does not link goes with the
/// island of its bodies where both are in one (or one does not move), and is set aside (the second list) otherwise.
pub(crate) fn joint_islands(
    bodies: &[BodyState],
    contacts: &[Contact],
    pairs: &[(usize, usize)],
    link: &[bool],
) -> (Vec<(Vec<usize>, Vec<usize>)>, Vec<usize>) {
    let moves = |b: usize| bodies[b].is_dynamic();
    let linking = contacts.iter().zip(link).filter(|(_, &l)| l).map(|(c, _)| (c.a, c.b));
    let mut uf = joined(bodies.len(), &moves, linking.chain(pairs.iter().copied()));
    let mut numbering = Numbering::new(bodies.len());
    let (mut out, mut apart) = (Vec::<(Vec<usize>, Vec<usize>)>::new(), Vec::new());
    let ends = contacts.iter().map(|c| (c.a, c.b)).chain(pairs.iter().copied());
    for (i, (a, b)) in ends.enumerate() {
        let root = uf.find(if moves(a) { a } else { b });
        if i < contacts.len() && moves(a) && moves(b) && uf.find(b) != root {
            apart.push(i);
            continue;
        }
        let k = numbering.of(root);
        if k == out.len() {
            out.push((Vec::new(), Vec::new()));
        }
        if i < contacts.len() {
            out[k].0.push(i);
        } else {
            out[k].1.push(i - contacts.len());
        }
    }
    (out, apart)
}

/// The union-find of `bodies` joined by `links`, only moving bodies (`moves`) joining.
fn joined(bodies: usize, moves: &impl Fn(usize) -> bool, links: impl Iterator<Item = (usize, usize)>) -> UnionFind {
    let mut uf = UnionFind::new(bodies);
    for (a, b) in links {
        if moves(a) && moves(b) {
            uf.union(a, b);
        }
    }
    uf
}

/// Islands numbered from zero in the order their roots are first asked for.
struct Numbering {
    index_of_root: Vec<usize>,
    count: usize,
}

impl Numbering {
    fn new(bodies: usize) -> Numbering {
        Numbering { index_of_root: vec![usize::MAX; bodies], count: 0 }
    }

    /// The number of the island whose root is `root`.
    fn of(&mut self, root: usize) -> usize {
        if self.index_of_root[root] == usize::MAX {
            self.index_of_root[root] = self.count;
            self.count += 1;
        }
        self.index_of_root[root]
    }
}

/// Islands of links between bodies (a body pair each: manifolds, joints, springs), only moving bodies joining them
/// (`moves`): each link's island, islands numbered in the order of their first link, and how many there are.
pub(crate) fn link_islands(
    bodies: usize,
    moves: impl Fn(usize) -> bool,
    links: impl Iterator<Item = (usize, usize)> + Clone,
) -> (Vec<usize>, usize) {
    let mut uf = joined(bodies, &moves, links.clone());
    let mut numbering = Numbering::new(bodies);
    let of_link = links.map(|(a, b)| numbering.of(uf.find(if moves(a) { a } else { b }))).collect();
    (of_link, numbering.count)
}

/// Each moving body's island among `bodies` joined by `links` (the islands numbered from zero in the order of their
/// first body), `usize::MAX` for a body that does not move; and how many islands there are.
pub fn body_islands(
    bodies: usize,
    moves: impl Fn(usize) -> bool,
    links: impl Iterator<Item = (usize, usize)>,
) -> (Vec<usize>, usize) {
    let mut uf = joined(bodies, &moves, links);
    let mut numbering = Numbering::new(bodies);
    let island = (0..bodies).map(|b| if moves(b) { numbering.of(uf.find(b)) } else { usize::MAX }).collect();
    (island, numbering.count)
}

#[cfg(test)]
mod body_island_tests {
    use super::body_islands;

    #[test]
    fn moving_bodies_are_numbered_by_island_and_fixed_ones_join_none() {
        // 0-1 linked, 3 alone, 2 fixed (links through it join nothing), 4 linked to 1 through the fixed 2? no: 4-2
        let moves = |b: usize| b != 2;
        let (island, count) = body_islands(5, moves, [(0, 1), (1, 2), (2, 4)].into_iter());
        assert_eq!(count, 3);
        assert_eq!(island, vec![0, 0, usize::MAX, 1, 2]);
    }
}
