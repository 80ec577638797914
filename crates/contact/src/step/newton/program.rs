//! The program of one island as tumble's Newton method sees it (`solve.rs`): the velocity unknowns and
//! their block-diagonal mass, the Jacobian rows with their constants, the blocks of rows with the sets their
//! impulses lie in and their proximal weights; the subproblem's impulses, gradient, Hessian and exact line search.

use crate::body::BodyState;
use crate::contact::{tangents, Contact};
use crate::impulse::BodyVelocity;
use crate::jacobian::{rows, Row};
use crate::step::island::bias;
use crate::step::problem::{BilateralKind, BilateralRow};
use crate::step::settings::StepSettings;
use nalgebra::{DVector, Matrix3, Vector3};

/// The first outer iteration's weight, raised tenfold each iteration up to `STIFFNESS` (a continuation: a soft
/// first subproblem has few kinks for Newton's method to cross and finds most of the active set; each stiffer one
/// starts from the last's answer).
pub(crate) const FIRST_STIFFNESS: f64 = 1e2;

/// An island's inputs: the bodies and contacts of the step, the lagged normal impulses, the island's contacts and
/// joint rows, the free velocities and settings, and its velocity unknowns (`offset` of each member, `n` in all).
#[derive(Clone, Copy)]
pub(crate) struct Island<'a> {
    pub bodies: &'a [BodyState],
    pub contacts: &'a [Contact],
    pub bounds: &'a [f64],
    pub island: &'a [usize],
    pub bilateral: &'a [&'a BilateralRow],
    pub free: &'a [BodyVelocity],
    pub s: &'a StepSettings,
    pub offset: &'a [usize],
    pub members: &'a [usize],
    pub n: usize,
}

/// What set a block's impulse lies in.
#[derive(Clone, Copy)]
pub(crate) enum Set {
    /// One row, its impulse within [lo, hi].
    Interval { lo: f64, hi: f64 },
    /// Two rows, their impulse within a disc of this radius.
    Disc(f64),
}

/// One block of rows: its first row, its set and its proximal weight.
#[derive(Clone, Copy)]
pub(crate) struct Block {
    pub row: usize,
    pub set: Set,
    pub rho: f64,
    /// rho as a multiple of the block's inverse effective mass (`STIFFNESS`, raised where the iteration is slow).
    pub stiffness: f64,
}

impl Block {
    pub fn width(&self) -> usize {
        match self.set {
            Set::Interval { .. } => 1,
            Set::Disc(_) => 2,
        }
    }

    /// The projection of y onto the block's set (into `out`), and its derivative (1 x 1 or 2 x 2, row-major).
    fn project(&self, y: &[f64], out: &mut [f64]) -> [f64; 4] {
        match self.set {
            Set::Interval { lo, hi } => {
                out[0] = y[0].clamp(lo, hi);
                [if lo < y[0] && y[0] < hi { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0]
            }
            Set::Disc(r) => {
                let n = (y[0] * y[0] + y[1] * y[1]).sqrt();
                if n <= r {
                    out[..2].copy_from_slice(&y[..2]);
                    [1.0, 0.0, 0.0, 1.0]
                } else {
                    let (d0, d1, s) = (y[0] / n, y[1] / n, r / n);
                    out[0] = r * d0;
                    out[1] = r * d1;
                    [s * (1.0 - d0 * d0), -s * d0 * d1, -s * d0 * d1, s * (1.0 - d1 * d1)]
                }
            }
        }
    }
}

/// One body's part of a Jacobian row: its first unknown, its width (3 for a particle, 6 for a rigid body: linear
/// then angular), the body, and the values.
#[derive(Clone, Copy, Default)]
pub(crate) struct Part {
    pub at: usize,
    pub len: usize,
    pub body: usize,
    pub values: [f64; 6],
}

/// A Jacobian row over the island's unknowns: the parts of its (at most two) moving bodies, and its constant.
#[derive(Clone, Default)]
pub(crate) struct SparseRow {
    parts: [Part; 2],
    count: usize,
    pub c: f64,
}

impl SparseRow {
    /// The row's parts, one per moving body.
    pub fn parts(&self) -> &[Part] {
        &self.parts[..self.count]
    }

    pub fn dot(&self, v: &[f64]) -> f64 {
        self.parts().iter().map(|p| (0..p.len).map(|k| p.values[k] * v[p.at + k]).sum::<f64>()).sum()
    }
}

/// One body's block of the mass matrix: its first unknown, its mass, and its inertia and inverse for a rigid body.
pub(crate) struct MassBlock {
    pub at: usize,
    pub mass: f64,
    pub inertia: Option<(Matrix3<f64>, Matrix3<f64>)>,
}

/// The island as the Newton iteration sees it.
pub(crate) struct Program {
    /// The mass matrix over the unknowns, block by block.
    pub mass: Vec<MassBlock>,
    /// The free velocities v*.
    pub free: DVector<f64>,
    pub rows: Vec<SparseRow>,
    pub blocks: Vec<Block>,
}

/// What the island's rows are: each contact's normal row and (with a friction bound) its two tangent rows, then the
/// joint rows; the velocity unknowns numbered by `offset`.
pub(crate) fn program(island: &Island<'_>) -> Program {
    let Island { bodies, contacts, bounds, island, bilateral, free, s, offset, members, n } = *island;
    let mut mass = Vec::with_capacity(members.len());
    let mut v_free = DVector::zeros(n);
    for &k in members {
        let (b, o) = (&bodies[k], offset[k]);
        for d in 0..3 {
            v_free[o + d] = free[k].linear[d];
        }
        if b.rotates() {
            for d in 0..3 {
                v_free[o + 3 + d] = free[k].angular[d];
            }
        }
        let inertia = b.rotates().then_some((b.inertia, b.inv_inertia));
        mass.push(MassBlock { at: o, mass: 1.0 / b.inv_mass, inertia });
    }
    let sparse = |parts: &[Row; 2], c: f64| {
        let mut row = SparseRow { c, ..SparseRow::default() };
        for p in parts {
            let b = &bodies[p.body];
            if !b.is_dynamic() {
                row.c += p.lin.dot(&free[p.body].linear) + p.ang.dot(&free[p.body].angular);
                continue;
            }
            let mut values = [0.0; 6];
            values[..3].copy_from_slice(p.lin.as_slice());
            values[3..].copy_from_slice(p.ang.as_slice());
            let len = if b.rotates() { 6 } else { 3 };
            match row.parts[..row.count].iter_mut().find(|q| q.body == p.body) {
                // (a row with both ends on one body: its parts add up)
                Some(q) => (0..6).for_each(|k| q.values[k] += values[k]),
                None => {
                    row.parts[row.count] = Part { at: offset[p.body], len, body: p.body, values };
                    row.count += 1;
                }
            }
        }
        row
    };
    // A_ii: the row's inverse effective mass, for its proximal weight
    let diagonal = |r: &SparseRow| {
        let mut sum = 0.0;
        for part in r.parts() {
            let b = &bodies[part.body];
            let lin = Vector3::new(part.values[0], part.values[1], part.values[2]);
            sum += lin.norm_squared() * b.inv_mass;
            if part.len == 6 {
                let ang = Vector3::new(part.values[3], part.values[4], part.values[5]);
                sum += ang.dot(&(b.inv_inertia * ang));
            }
        }
        sum.max(f64::MIN_POSITIVE)
    };
    let (mut out_rows, mut blocks) = (Vec::new(), Vec::new());
    for &i in island {
        let c = &contacts[i];
        let nrm = c.normal.into_inner();
        let normal = sparse(&rows(c, bodies, &nrm), bias(c, bodies, s));
        let rho = FIRST_STIFFNESS / diagonal(&normal);
        blocks.push(Block {
            row: out_rows.len(),
            set: Set::Interval { lo: 0.0, hi: f64::INFINITY },
            rho,
            stiffness: FIRST_STIFFNESS,
        });
        out_rows.push(normal);
        let radius = c.friction * bounds[i];
        if radius > 0.0 {
            let (t1, t2) = tangents(&nrm);
            let (r1, r2) = (sparse(&rows(c, bodies, &t1), 0.0), sparse(&rows(c, bodies, &t2), 0.0));
            let rho = 2.0 * FIRST_STIFFNESS / (diagonal(&r1) + diagonal(&r2));
            blocks.push(Block { row: out_rows.len(), set: Set::Disc(radius), rho, stiffness: FIRST_STIFFNESS });
            out_rows.extend([r1, r2]);
        }
    }
    for r in bilateral {
        let parts = [Row { body: r.a, lin: -r.lin, ang: r.ang_a }, Row { body: r.b, lin: r.lin, ang: r.ang_b }];
        let row = sparse(&parts, -r.speed);
        let (lo, hi) = match r.kind {
            BilateralKind::Equal => (f64::NEG_INFINITY, f64::INFINITY),
            BilateralKind::AtLeast => (0.0, f64::INFINITY),
            BilateralKind::Motor { max_impulse } => (-max_impulse, max_impulse),
        };
        let rho = FIRST_STIFFNESS / diagonal(&row);
        blocks.push(Block { row: out_rows.len(), set: Set::Interval { lo, hi }, rho, stiffness: FIRST_STIFFNESS });
        out_rows.push(row);
    }
    Program { mass, free: v_free, rows: out_rows, blocks }
}

impl Program {
    /// M x (inverse: M^-1 x).
    pub fn mass_times(&self, x: &DVector<f64>, inverse: bool) -> DVector<f64> {
        let mut out = DVector::zeros(x.len());
        for b in &self.mass {
            let o = b.at;
            let m = if inverse { 1.0 / b.mass } else { b.mass };
            for d in 0..3 {
                out[o + d] = m * x[o + d];
            }
            if let Some((i, inv)) = &b.inertia {
                let w = Vector3::new(x[o + 3], x[o + 4], x[o + 5]);
                let r = if inverse { inv * w } else { i * w };
                out.fixed_rows_mut::<3>(o + 3).copy_from(&r);
            }
        }
        out
    }

    /// u = J v + c.
    pub fn row_velocities(&self, v: &[f64]) -> Vec<f64> {
        self.rows.iter().map(|r| r.dot(v) + r.c).collect()
    }

    /// The subproblem's impulses P_K(lambda_k - rho u) at row velocities u, and each block's derivative.
    pub fn impulses(&self, prior: &[f64], u: &[f64], out: &mut [f64], derivatives: Option<&mut Vec<[f64; 4]>>) {
        let mut y = [0.0; 2];
        let mut ds = derivatives;
        for b in &self.blocks {
            let w = b.width();
            for k in 0..w {
                y[k] = prior[b.row + k] - b.rho * u[b.row + k];
            }
            let d = b.project(&y[..w], &mut out[b.row..b.row + w]);
            if let Some(ds) = ds.as_deref_mut() {
                ds.push(d);
            }
        }
    }

    /// J^T lambda over the unknowns.
    pub fn spread(&self, lambda: &[f64]) -> DVector<f64> {
        let mut out = DVector::zeros(self.free.len());
        for (r, l) in self.rows.iter().zip(lambda) {
            for p in r.parts() {
                for k in 0..p.len {
                    out[p.at + k] += p.values[k] * l;
                }
            }
        }
        out
    }

    /// The exact minimiser of the subproblem along dv within (0, 1], by safeguarded Newton on the slope (convex and
    /// piecewise quadratic, so Newton is exact within a piece), given u(v) = J v + c.
    pub fn line_search(&self, prior: &[f64], v: &DVector<f64>, dv: &DVector<f64>, u0: &[f64]) -> f64 {
        let jdv: Vec<f64> = self.rows.iter().map(|r| r.dot(dv.as_slice())).collect();
        let mdv = self.mass_times(dv, false);
        // the mass term's slope at alpha is base + alpha curvature
        let (base, curvature) = (mdv.dot(&(v - &self.free)), mdv.dot(dv));
        let (mut u, mut lambda) = (vec![0.0; u0.len()], vec![0.0; u0.len()]);
        let mut ds = Vec::with_capacity(self.blocks.len());
        // the slope at v + alpha dv and its second derivative
        let mut slope = |alpha: f64| {
            for ((u, a), b) in u.iter_mut().zip(u0).zip(&jdv) {
                *u = a + alpha * b;
            }
            ds.clear();
            self.impulses(prior, &u, &mut lambda, Some(&mut ds));
            let first = base + alpha * curvature - jdv.iter().zip(&lambda).map(|(a, b)| a * b).sum::<f64>();
            let mut second = curvature;
            for (b, d) in self.blocks.iter().zip(&ds) {
                let w = b.width();
                for p in 0..w {
                    for q in 0..w {
                        second += b.rho * d[p * 2 + q] * jdv[b.row + p] * jdv[b.row + q];
                    }
                }
            }
            (if first.is_finite() { first } else { f64::NAN }, second)
        };
        let (f0, _) = slope(0.0);
        let (mut f, mut df) = slope(1.0);
        if !(f0 < 0.0) || f <= 0.0 {
            return 1.0;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut alpha = 1.0;
        for _ in 0..50 {
            if f.abs() <= 1e-12 * f0.abs() {
                break;
            }
            if f < 0.0 {
                lo = alpha;
            } else {
                hi = alpha;
            }
            let newton = alpha - f / df;
            alpha = if df > 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
            if hi - lo <= 1e-14 {
                break;
            }
            (f, df) = slope(alpha);
        }
        alpha
    }
}
