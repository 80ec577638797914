//! Union-find over n items, each set's root its smallest member: the one grouping of the workspace (contact
//! islands, sleeping groups, glued pieces), its roots naming the sets the same way whatever order the unions came in.

/// Disjoint sets of the items 0..n, by parent links with path halving.
#[derive(Clone, Debug)]
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    /// n items, each alone.
    pub fn new(n: usize) -> Self {
        UnionFind { parent: (0..n).collect() }
    }

    /// The root of `x`'s set: its smallest member.
    pub fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    /// Joins the sets of `a` and `b` (the larger root points to the smaller).
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        self.parent[ra.max(rb)] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::UnionFind;

    #[test]
    fn roots_are_the_smallest_members_whatever_the_order_of_unions() {
        let pairs = [(5, 3), (7, 5), (1, 8), (8, 2), (9, 9)];
        let mut forward = UnionFind::new(10);
        let mut backward = UnionFind::new(10);
        pairs.iter().for_each(|&(a, b)| forward.union(a, b));
        pairs.iter().rev().for_each(|&(a, b)| backward.union(b, a));
        let roots = |uf: &mut UnionFind| (0..10).map(|x| uf.find(x)).collect::<Vec<_>>();
        assert_eq!(roots(&mut forward), vec![0, 1, 1, 3, 4, 3, 6, 3, 1, 9]);
        assert_eq!(roots(&mut forward), roots(&mut backward));
    }
}
