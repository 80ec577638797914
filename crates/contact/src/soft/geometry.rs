//! A bundle's geometry in lanes: its constraint axes completed once a step (`build`: Jacobians, inverse inertia
//! times them, effective masses) and its points' gaps once a substep as the bodies move (`update_gaps`).

use super::bundle::{Arms, Bundle, FrictionBundle};
use super::row::Mover;
use super::wide::{dot, wide3, Vec3Lanes, Wide, W};

/// Every point's gap where the substeps have moved the bodies: the gap at the step's start plus the normal part of
/// how far B's material point moved against A's.
pub(crate) fn update_gaps(bundles: &mut [Bundle], arms: &[Arms], movers: &[Mover]) {
    #[cfg(target_arch = "x86_64")]
    if super::bundle::avx2() {
        // SAFETY: as in `sweep`.
        return unsafe { update_gaps_avx2(bundles, arms, movers) };
    }
    update_gaps_lanes(bundles, arms, movers)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn update_gaps_avx2(bundles: &mut [Bundle], arms: &[Arms], movers: &[Mover]) {
    update_gaps_lanes(bundles, arms, movers)
}

/// Each lane's body's displacement and turn since the step's start.
#[inline(always)]
fn motion(side: &[usize; W], lanes: usize, movers: &[Mover]) -> ([Wide; 3], [[Wide; 3]; 3]) {
    let (mut dp, mut turn) = ([Wide::default(); 3], [[Wide::default(); 3]; 3]);
    for (l, &m) in side.iter().enumerate().take(lanes) {
        let m = &movers[m];
        for (i, row) in turn.iter_mut().enumerate() {
            dp[i].0[l] = m.dp[i];
            for (j, x) in row.iter_mut().enumerate() {
                x.0[l] = m.turn[(i, j)];
            }
        }
    }
    (dp, turn)
}

/// How far the material point at arm r moved: dp + turn r - r.
#[inline(always)]
fn moved(dp: &[Wide; 3], turn: &[[Wide; 3]; 3], r: &Vec3Lanes) -> [Wide; 3] {
    let r = wide3(r);
    let turned = times(turn, &r);
    [dp[0] + (turned[0] - r[0]), dp[1] + (turned[1] - r[1]), dp[2] + (turned[2] - r[2])]
}

/// A matrix (by rows of lanes) times a vector.
#[inline(always)]
fn times(m: &[[Wide; 3]; 3], c: &[Wide; 3]) -> [Wide; 3] {
    let row = |i: usize| m[i][0] * c[0] + m[i][1] * c[1] + m[i][2] * c[2];
    [row(0), row(1), row(2)]
}

#[inline(always)]
fn update_gaps_lanes(bundles: &mut [Bundle], arms: &[Arms], movers: &[Mover]) {
    for (bu, arm) in bundles.iter_mut().zip(arms) {
        let (dpa, ta) = motion(&bu.a, bu.lanes, movers);
        let (dpb, tb) = motion(&bu.b, bu.lanes, movers);
        for p in 0..bu.points {
            let (ma, mb) = (moved(&dpa, &ta, &arm.ra[p]), moved(&dpb, &tb, &arm.rb[p]));
            let d = [mb[0] - ma[0], mb[1] - ma[1], mb[2] - ma[2]];
            bu.rows[p].gap = (Wide(arm.gap[p]) + dot(&wide3(&bu.rows[p].normal_axis.dir), &d)).0;
        }
    }
}

/// Completes every axis whose direction is set: the angular Jacobians r_a x d and r_b x d, the inverse inertia
/// times them, and the effective mass 1 / (J M^-1 J^T) (zero on a lane's points past its count): each point's
/// normal row, the friction rows at the friction centre, and the twist about the normal (set in its `ca`).
pub(crate) fn build(bundles: &mut [Bundle], frictions: &mut [FrictionBundle], arms: &[Arms], movers: &[Mover]) {
    #[cfg(target_arch = "x86_64")]
    if super::bundle::avx2() {
        // SAFETY: as in `sweep`.
        return unsafe { build_avx2(bundles, frictions, arms, movers) };
    }
    build_lanes(bundles, frictions, arms, movers)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn build_avx2(bundles: &mut [Bundle], frictions: &mut [FrictionBundle], arms: &[Arms], movers: &[Mover]) {
    build_lanes(bundles, frictions, arms, movers)
}

#[inline(always)]
fn cross(a: &[Wide; 3], b: &[Wide; 3]) -> [Wide; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Each lane's body's inverse inertia.
#[inline(always)]
fn inertia(side: &[usize; W], lanes: usize, movers: &[Mover]) -> [[Wide; 3]; 3] {
    let mut m = [[Wide::default(); 3]; 3];
    for (l, &k) in side.iter().enumerate().take(lanes) {
        for (i, row) in m.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                x.0[l] = movers[k].inv_inertia[(i, j)];
            }
        }
    }
    m
}

/// Completes axis `axis` (its direction set) at arms `ra`, `rb`: the angular Jacobians r x d, the inverse inertia
/// times them and the effective mass (zero where `used` is not).
#[inline(always)]
fn complete(
    axis: &mut super::bundle::AxisLanes,
    (ra, rb): (&[Wide; 3], &[Wide; 3]),
    (ia, ib): (&[[Wide; 3]; 3], &[[Wide; 3]; 3]),
    (ima, imb): (Wide, Wide),
    used: [bool; W],
) {
    let d = wide3(&axis.dir);
    let (ca, cb) = (cross(ra, &d), cross(rb, &d));
    angular(axis, (ca, cb), (ia, ib), (ima, imb), used);
}

/// Completes axis `axis` from its angular Jacobians `ca`, `cb`: the inverse inertia times them and the effective
/// mass (with the linear part of its direction).
#[inline(always)]
fn angular(
    axis: &mut super::bundle::AxisLanes,
    (ca, cb): ([Wide; 3], [Wide; 3]),
    (ia, ib): (&[[Wide; 3]; 3], &[[Wide; 3]; 3]),
    (ima, imb): (Wide, Wide),
    used: [bool; W],
) {
    let zero = Wide::splat(0.0);
    let d = wide3(&axis.dir);
    let (ja, jb) = (times(ia, &ca), times(ib, &cb));
    let k = (ima + imb) * dot(&d, &d) + dot(&ca, &ja) + dot(&cb, &jb);
    let mass = Wide::select(k.gt(zero), Wide::splat(1.0) / k, zero);
    axis.mass = Wide::select(used, mass, zero).0;
    axis.ca = ca.map(|x| x.0);
    axis.cb = cb.map(|x| x.0);
    axis.ia = ja.map(|x| x.0);
    axis.ib = jb.map(|x| x.0);
}

#[inline(always)]
fn build_lanes(bundles: &mut [Bundle], frictions: &mut [FrictionBundle], arms: &[Arms], movers: &[Mover]) {
    for ((bu, fr), arm) in bundles.iter_mut().zip(frictions.iter_mut()).zip(arms) {
        let (ia, ib) = (inertia(&bu.a, bu.lanes, movers), inertia(&bu.b, bu.lanes, movers));
        let masses = (Wide(bu.ima), Wide(bu.imb));
        for p in 0..bu.points {
            let used: [bool; W] = std::array::from_fn(|l| p < bu.count[l]);
            let (ra, rb) = (wide3(&arm.ra[p]), wide3(&arm.rb[p]));
            complete(&mut bu.rows[p].normal_axis, (&ra, &rb), (&ia, &ib), masses, used);
        }
        let used: [bool; W] = std::array::from_fn(|l| l < bu.lanes);
        let (ca, cb) = (wide3(&arm.centre_a), wide3(&arm.centre_b));
        for axis in &mut fr.axes {
            complete(axis, (&ca, &cb), (&ia, &ib), masses, used);
        }
        // the tangent rows' K and its inverse (their linear parts are orthogonal)
        let [t0, t1] = &fr.axes;
        let k = |a: &super::bundle::AxisLanes, b: &super::bundle::AxisLanes| {
            let (ca, cb, ja, jb) = (wide3(&a.ca), wide3(&a.cb), wide3(&b.ia), wide3(&b.ib));
            let (ima, imb) = masses;
            (ima + imb) * dot(&wide3(&a.dir), &wide3(&b.dir)) + dot(&ca, &ja) + dot(&cb, &jb)
        };
        let (k00, k01, k11) = (k(t0, t0), k(t0, t1), k(t1, t1));
        let zero = Wide::splat(0.0);
        let det = k00 * k11 - k01 * k01;
        let inverse = Wide::select(det.gt(zero), Wide::splat(1.0) / det, zero);
        let inverse = Wide::select(used, inverse, zero);
        fr.block = [(k11 * inverse).0, (k01.neg() * inverse).0, (k00 * inverse).0];
        // the twist: angular alone, about the normal (its direction in `ca`, `cb` as set; no linear part)
        let n = wide3(&fr.twist_axis.ca);
        angular(&mut fr.twist_axis, (n, n), (&ia, &ib), masses, used);
        if fr.resists {
            // the rolling rows: angular alone about the tangents, their 2 x 2 K (no linear part) and its inverse
            for axis in &mut fr.roll_axes {
                let t = wide3(&axis.ca);
                angular(axis, (t, t), (&ia, &ib), masses, used);
            }
            let [r0, r1] = &fr.roll_axes;
            let k = |a: &super::bundle::AxisLanes, b: &super::bundle::AxisLanes| {
                dot(&wide3(&a.ca), &wide3(&b.ia)) + dot(&wide3(&a.cb), &wide3(&b.ib))
            };
            let (k00, k01, k11) = (k(r0, r0), k(r0, r1), k(r1, r1));
            let det = k00 * k11 - k01 * k01;
            let inverse = Wide::select(det.gt(zero), Wide::splat(1.0) / det, zero);
            let inverse = Wide::select(used, inverse, zero);
            fr.roll_block = [(k11 * inverse).0, (k01.neg() * inverse).0, (k00 * inverse).0];
        }
    }
}
