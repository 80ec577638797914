//! The Newton method's Hessian M + J^T rho dP J over an island's velocities (`solve.rs`), assembled body
//! block by body block and factorised by Cholesky: dense (faer) for a lone body, sparse with its symbolic
//! analysis done once per program for more (a pile's island couples each body to a few neighbours: the
//! 20-cube pile's 108 unknowns hold about a fifth of a dense lower triangle).

use super::program::Program;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Par, Side};
use nalgebra::DVector;

/// Islands with at least this many velocity unknowns are factorised sparse (measured on the 20-cube pile, time a
/// Newton iteration dense / sparse: 1.5 / 1.4 us below 12 unknowns, 2.8 / 2.6 at 12-23, 5.2 / 3.9 at 24-35, 15.6 /
/// 15.4 at 48-59, 36 / 29 at 72-83, 45 / 31 at 108-119; a lone body stays dense, the reference the sparse path is
/// tested against).
const SPARSE_FROM: usize = 12;

/// The Hessian's storage: a dense column-major square (the lower triangle read; assembled there on either path),
/// and for a sparse island its factorisation's parts (`SparseParts`).
pub(crate) struct Hessian {
    n: usize,
    dense: Vec<f64>,
    sparse: Option<SparseParts>,
}

/// A sparse island's factorisation: the Hessian's upper triangle (every entry a row of the program can reach) with
/// the bodies in a minimum-degree order, found once per program and stored in the order and on the side faer's
/// factorisation reads, so nothing is permuted per iteration; its symbolic factorisation, where each stored entry
/// sits in the dense square, and the numeric factor's and the workspace's storage, kept from iteration to
/// iteration.
struct SparseParts {
    structure: SymbolicSparseColMat<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// The order: unknown `order[k]` is the k-th of the factorisation.
    order: Vec<usize>,
    gather: Vec<usize>,
    values: Vec<f64>,
    factor: Vec<f64>,
    work: MemBuffer,
}

impl Hessian {
    /// The storage for `program`'s Hessian, with the sparse structure analysed where the island is large.
    pub fn new(program: &Program) -> Option<Hessian> {
        Hessian::stored(program, program.free.len() >= SPARSE_FROM)
    }

    /// The storage, sparse or dense as asked.
    fn stored(program: &Program, sparse: bool) -> Option<Hessian> {
        let n = program.free.len();
        let sparse = if sparse { Some(SparseParts::new(program, n)?) } else { None };
        Some(Hessian { n, dense: vec![0.0; n * n], sparse })
    }

    /// Assembles M + J^T rho dP J from the blocks' projection derivatives (lower triangle; each body pair's block
    /// written as whole columns).
    pub fn assemble(&mut self, p: &Program, derivatives: &[[f64; 4]]) {
        let n = self.n;
        let h = &mut self.dense;
        h.fill(0.0);
        for b in &p.mass {
            for d in 0..3 {
                h[(b.at + d) * (n + 1)] = b.mass;
            }
            if let Some((i, _)) = &b.inertia {
                for c in 0..3 {
                    for r in 0..3 {
                        h[(b.at + 3 + r) + (b.at + 3 + c) * n] = i[(r, c)];
                    }
                }
            }
        }
        for (b, d) in p.blocks.iter().zip(derivatives) {
            let w = b.width();
            // the block's rows weighted: z_q = sum_p rho d[p][q] J_p, so its term is sum_q z_q J_q^T
            for q in 0..w {
                let row_q = &p.rows[b.row + q];
                let mut z = [[0.0; 6]; 2];
                let mut any = false;
                for pp in 0..w {
                    let g = b.rho * d[pp * 2 + q];
                    if g == 0.0 {
                        continue;
                    }
                    any = true;
                    for (zk, part) in z.iter_mut().zip(p.rows[b.row + pp].parts()) {
                        for k in 0..part.len {
                            zk[k] += g * part.values[k];
                        }
                    }
                }
                if !any {
                    continue;
                }
                let parts_p = p.rows[b.row].parts();
                for (zk, a) in z.iter().zip(parts_p) {
                    // the term z_a c^T where it falls in the lower triangle (above it, its mirror is the term of
                    // the swapped pair of bodies, z_c a^T: g is symmetric)
                    for c in row_q.parts().iter().filter(|c| a.at >= c.at) {
                        add_outer(h, n, (a.at, &zk[..a.len]), (c.at, &c.values[..c.len]));
                    }
                }
            }
        }
    }

    /// Solves H x = rhs by Cholesky; `None` when H is not positive definite to working precision.
    pub fn solve(&mut self, rhs: &DVector<f64>) -> Option<DVector<f64>> {
        let n = self.n;
        let mut x = faer::Col::<f64>::from_fn(n, |i| rhs[i]);
        match &mut self.sparse {
            None => {
                let h = faer::MatRef::from_column_major_slice(&self.dense, n, n);
                h.llt(Side::Lower).ok()?.solve_in_place(x.as_mat_mut());
            }
            Some(s) => {
                for (v, &at) in s.values.iter_mut().zip(&s.gather) {
                    *v = self.dense[at];
                }
                let a = SparseColMatRef::new(s.structure.as_ref(), &s.values);
                let stack = MemStack::new(&mut s.work);
                let llt = s
                    .symbolic
                    .factorize_numeric_llt(
                        &mut s.factor,
                        a,
                        Side::Upper,
                        Default::default(),
                        Par::Seq,
                        stack,
                        Default::default(),
                    )
                    .ok()?;
                let mut y = faer::Col::<f64>::from_fn(n, |k| x[s.order[k]]);
                llt.solve_in_place_with_conj(Conj::No, y.as_mat_mut(), Par::Seq, MemStack::new(&mut s.work));
                for (k, &i) in s.order.iter().enumerate() {
                    x[i] = y[k];
                }
            }
        }
        Some(DVector::from_fn(n, |i, _| x[i]))
    }
}

/// h[ra + i, cb + j] += x_i y_j over the block (column-major h of side n; entries above the diagonal of a
/// diagonal block are written too and never read).
fn add_outer(h: &mut [f64], n: usize, (ra, x): (usize, &[f64]), (cb, y): (usize, &[f64])) {
    for (j, &yj) in y.iter().enumerate() {
        let column = &mut h[(cb + j) * n + ra..(cb + j) * n + ra + x.len()];
        for (hij, &xi) in column.iter_mut().zip(x) {
            *hij += xi * yj;
        }
    }
}

impl SparseParts {
    /// The structure: each body's own block and each pair of bodies a row joins, whole blocks, with the bodies in
    /// a minimum-degree order (so each body's unknowns stay together and the structure is built without sorting).
    fn new(p: &Program, n: usize) -> Option<SparseParts> {
        // the bodies (blocks of the mass matrix) and the pairs of them the rows join
        let mut body_at = vec![usize::MAX; n];
        for (k, b) in p.mass.iter().enumerate() {
            body_at[b.at] = k;
        }
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for r in &p.rows {
            if let [a, c] = r.parts() {
                let (a, c) = (body_at[a.at], body_at[c.at]);
                if a != c {
                    pairs.push((a.min(c), a.max(c)));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        let bodies = p.mass.len();
        let order = minimum_degree(bodies, &pairs);
        let mut rank = vec![0; bodies];
        for (k, &b) in order.iter().enumerate() {
            rank[b] = k;
        }
        // the unknowns in that order, and where each body's first lands
        let len = |b: usize| if p.mass[b].inertia.is_some() { 6 } else { 3 };
        let mut first = vec![0; bodies];
        let mut unknowns = Vec::with_capacity(n);
        for &b in &order {
            first[b] = unknowns.len();
            unknowns.extend(p.mass[b].at..p.mass[b].at + len(b));
        }
        // each body's neighbours earlier in the order, in order
        let mut earlier: Vec<Vec<usize>> = vec![Vec::new(); bodies];
        for &(a, c) in &pairs {
            let (lo, hi) = if rank[a] < rank[c] { (a, c) } else { (c, a) };
            earlier[hi].push(lo);
        }
        // the upper triangle of the reordered Hessian: column l of body B holds the rows of B's earlier neighbours
        // and of B itself up to l; its entry (k, l) is the original's at (unknowns[k], unknowns[l]), stored in the
        // dense square's lower triangle
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for &b in &order {
            earlier[b].sort_unstable_by_key(|&c| rank[c]);
            for l in first[b]..first[b] + len(b) {
                for &c in &earlier[b] {
                    row_idx.extend(first[c]..first[c] + len(c));
                }
                row_idx.extend(first[b]..=l);
                col_ptr.push(row_idx.len());
            }
        }
        let mut gather = Vec::with_capacity(row_idx.len());
        for l in 0..n {
            for &k in &row_idx[col_ptr[l]..col_ptr[l + 1]] {
                let (a, b) = (unknowns[k], unknowns[l]);
                gather.push(a.max(b) + a.min(b) * n);
            }
        }
        let structure = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic = factorize_symbolic_cholesky(
            structure.as_ref(),
            Side::Upper,
            SymmetricOrdering::Identity,
            Default::default(),
        )
        .ok()?;
        let req = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let (values, factor) = (vec![0.0; gather.len()], vec![0.0; symbolic.len_val()]);
        let order = unknowns;
        Some(SparseParts { structure, symbolic, order, gather, values, factor, work: MemBuffer::try_new(req).ok()? })
    }
}

/// A minimum-degree elimination order of a graph of `nodes` nodes with edges `pairs` (each once): the node of fewest
/// neighbours in the graph as eliminated so far goes next (ties to the lower index), its neighbours joined to each
/// other. A pile's islands have a few dozen bodies, so the quadratic search costs nothing beside a factorisation.
fn minimum_degree(nodes: usize, pairs: &[(usize, usize)]) -> Vec<usize> {
    let mut adjacent: Vec<std::collections::BTreeSet<usize>> = vec![Default::default(); nodes];
    for &(a, b) in pairs {
        adjacent[a].insert(b);
        adjacent[b].insert(a);
    }
    let mut done = vec![false; nodes];
    let mut order = Vec::with_capacity(nodes);
    while let Some(next) = (0..nodes).filter(|&i| !done[i]).min_by_key(|&i| (adjacent[i].len(), i)) {
        done[next] = true;
        order.push(next);
        let neighbours: Vec<usize> = std::mem::take(&mut adjacent[next]).into_iter().collect();
        for &a in &neighbours {
            adjacent[a].remove(&next);
            adjacent[a].extend(neighbours.iter().copied().filter(|&b| b != a));
        }
    }
    order
}

#[cfg(test)]
mod tests {
    use super::super::program::{program, Island, Set};
    use super::*;
    use crate::body::BodyState;
    use crate::contact::Contact;
    use crate::impulse::BodyVelocity;
    use crate::step::StepSettings;
    use nalgebra::{DMatrix, Matrix3, Point3, Unit, Vector3};

    /// A random island: a stack of rigid bodies and particles on the ground, each on the one below through 1-3
    /// points, with lagged bounds (so every contact has a friction disc).
    fn random_program(seed: u64) -> Program {
        let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let mut u = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let count = 14;
        let mut bodies = vec![BodyState::fixed(Point3::origin())];
        let mut contacts = Vec::new();
        for k in 1..=count {
            let m = 10f64.powf(-1.0 + 2.0 * u());
            let p = Point3::new(u() - 0.5, u() - 0.5, k as f64 * 0.3);
            bodies.push(if k % 4 == 0 {
                BodyState::particle(m, p, Vector3::zeros())
            } else {
                let c = 0.1 * u();
                let i = Matrix3::new(1.0 + u(), c, 0.0, c, 1.0 + u(), 0.0, 0.0, 0.0, 1.0 + u());
                BodyState::rigid(m, i * (0.05 * m), p)
            });
            let on = (u() * k as f64) as usize;
            for _ in 0..1 + (u() * 3.0) as usize {
                let at = p + Vector3::new(u() - 0.5, u() - 0.5, -0.1) * 0.2;
                let normal = Unit::new_normalize(Vector3::new(0.3 * (u() - 0.5), 0.3 * (u() - 0.5), 1.0));
                contacts.push(Contact::new(on, k, at, normal).with_friction(0.5));
            }
        }
        let members: Vec<usize> = (1..=count).collect();
        let mut offset = vec![0; count + 1];
        let mut n = 0;
        for &k in &members {
            offset[k] = n;
            n += if bodies[k].rotates() { 6 } else { 3 };
        }
        let bounds: Vec<f64> = contacts.iter().map(|_| 0.1 + u()).collect();
        let island: Vec<usize> = (0..contacts.len()).collect();
        let free: Vec<BodyVelocity> =
            bodies.iter().map(|b| BodyVelocity { linear: b.velocity, angular: b.angular_velocity }).collect();
        let s = StepSettings::new(0.01);
        let input = Island {
            bodies: &bodies,
            contacts: &contacts,
            bounds: &bounds,
            island: &island,
            bilateral: &[],
            free: &free,
            s: &s,
            offset: &offset,
            members: &members,
            n,
        };
        program(&input)
    }

    /// Random projection derivatives of the kinds a block has: 0 or 1 for an interval, and for a disc either the
    /// identity (inside) or s (I - d d^T) (on its rim).
    fn derivatives(p: &Program, seed: u64) -> Vec<[f64; 4]> {
        p.blocks
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let r = ((seed as usize + 7 * k) % 11) as f64 / 11.0;
                match b.set {
                    Set::Interval { .. } => [if r < 0.7 { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0],
                    Set::Disc(_) if r < 0.3 => [1.0, 0.0, 0.0, 1.0],
                    Set::Disc(_) => {
                        let (c, s, scale) = ((6.0 * r).cos(), (6.0 * r).sin(), 0.2 + r);
                        [scale * (1.0 - c * c), -scale * c * s, -scale * c * s, scale * (1.0 - s * s)]
                    }
                }
            })
            .collect()
    }

    /// M + J^T rho dP J the plain way: the rows as dense vectors.
    fn by_definition(p: &Program, ds: &[[f64; 4]]) -> DMatrix<f64> {
        let n = p.free.len();
        let row = |r: usize| -> Vec<f64> {
            (0..n)
                .map(|i| {
                    let mut e = vec![0.0; n];
                    e[i] = 1.0;
                    p.rows[r].dot(&e)
                })
                .collect()
        };
        let mut h = DMatrix::zeros(n, n);
        for i in 0..n {
            let mut e = nalgebra::DVector::zeros(n);
            e[i] = 1.0;
            h.set_column(i, &p.mass_times(&e, false));
        }
        for (b, d) in p.blocks.iter().zip(ds) {
            let w = b.width();
            for a in 0..w {
                for c in 0..w {
                    let (ja, jc) = (row(b.row + a), row(b.row + c));
                    for i in 0..n {
                        for j in 0..n {
                            h[(i, j)] += b.rho * d[a * 2 + c] * ja[i] * jc[j];
                        }
                    }
                }
            }
        }
        h
    }

    /// The assembled lower triangle is the definition's, and the sparse and dense factorisations solve alike.
    #[test]
    fn assembly_and_both_factorisations_match_the_definition() {
        for seed in 0..10 {
            let p = random_program(seed);
            let ds = derivatives(&p, seed);
            let exact = by_definition(&p, &ds);
            let n = p.free.len();
            let scale = exact.amax();
            let rhs = nalgebra::DVector::from_fn(n, |i, _| ((i * 37 + seed as usize) % 13) as f64 - 6.0);
            let mut answers = Vec::new();
            for sparse in [false, true] {
                let mut h = Hessian::stored(&p, sparse).expect("the structure is analysed");
                h.assemble(&p, &ds);
                for j in 0..n {
                    for i in j..n {
                        // sums of a few dozen products of rounded terms: 1e-13 of the largest entry
                        let got = h.dense[i + j * n];
                        assert!((got - exact[(i, j)]).abs() <= 1e-13 * scale, "seed {seed} ({i}, {j})");
                    }
                }
                answers.push(h.solve(&rhs).expect("positive definite"));
            }
            // both backward stable against the definition (residual to rounding times the sizes), and agreeing to
            // 1e-8 of the answer's size (their rounding amplified by the Hessian's condition: masses over two decades
            // and proximal weights 1e2 over the rows' own)
            for x in &answers {
                let residual = (&exact * x - &rhs).amax() / (scale * x.amax());
                assert!(residual < 1e-12, "seed {seed}: residual {residual:e}");
            }
            assert!((&answers[0] - &answers[1]).amax() <= 1e-8 * answers[0].amax(), "seed {seed}");
        }
    }
}
