//! The faces pieces share: where a triangle of one piece and a triangle of another lie on one plane facing each
//! other, the area they overlap in. Found from the pieces alone, so that any set of pieces (a fracture's, or pieces
//! modelled by hand) can be glued.

use crate::surface_mesh::{extent, Mesh};
use nalgebra::{Point2, Point3, Vector3};

/// A face two pieces share: pieces `a` < `b` (indices into the slice given), its `area` (m^2), its `centre`
/// (the area's centroid) and its `normal` (unit, out of `a` into `b`), in the pieces' common frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SharedFace {
    pub a: usize,
    pub b: usize,
    pub area: f64,
    pub centre: Point3<f64>,
    pub normal: Vector3<f64>,
}

/// Triangles face each other where their unit normals' dot product is below -1 + this.
const FACING: f64 = 1e-8;
/// And lie on one plane where each corner of one is within this share of the pieces' size of the other's plane.
const COPLANAR: f64 = 1e-9;
/// A shared face smaller than this share of the size squared is rounding, not a face.
const SMALLEST: f64 = 1e-12;

/// One triangle of one piece, with its plane.
struct Facet {
    piece: usize,
    corners: [Point3<f64>; 3],
    normal: Vector3<f64>,
}

/// The faces the `pieces` (all in one frame) share, each pair once, ordered by pair.
pub fn shared_faces(pieces: &[Mesh]) -> Vec<SharedFace> {
    let all: Vec<Point3<f64>> = pieces.iter().flat_map(|m| m.vertices().iter().copied()).collect();
    let size = extent(&all);
    let mut facets: Vec<Facet> = Vec::new();
    for (piece, m) in pieces.iter().enumerate() {
        let v = m.vertices();
        for t in m.triangles() {
            let corners = t.map(|k| v[k as usize]);
            let n = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
            if let Some(normal) = n.try_normalize(0.0) {
                facets.push(Facet { piece, corners, normal });
            }
        }
    }
    // facing triangles have opposite normals: sorted by the normal's x, each looks for -x among the others
    let mut order: Vec<usize> = (0..facets.len()).collect();
    order.sort_by(|&i, &j| facets[i].normal.x.total_cmp(&facets[j].normal.x).then(i.cmp(&j)));
    let xs: Vec<f64> = order.iter().map(|&i| facets[i].normal.x).collect();
    // by pair: area, area times centroid, area times normal
    let mut found: std::collections::BTreeMap<(usize, usize), (f64, Vector3<f64>, Vector3<f64>)> = Default::default();
    for f in &facets {
        let from = xs.partition_point(|&x| x < -f.normal.x - FACING.sqrt());
        for &k in &order[from..] {
            let g = &facets[k];
            if g.normal.x > -f.normal.x + FACING.sqrt() {
                break;
            }
            if g.piece <= f.piece || f.normal.dot(&g.normal) > -1.0 + FACING {
                continue;
            }
            if g.corners.iter().any(|c| f.normal.dot(&(c - f.corners[0])).abs() > COPLANAR * size) {
                continue;
            }
            if let Some((area, centre)) = overlap(f, g) {
                if area > SMALLEST * size * size {
                    let e = found.entry((f.piece, g.piece)).or_insert((0.0, Vector3::zeros(), Vector3::zeros()));
                    e.0 += area;
                    e.1 += centre.coords * area;
                    e.2 += f.normal * area;
                }
            }
        }
    }
    found
        .into_iter()
        .map(|((a, b), (area, moment, normal))| SharedFace {
            a,
            b,
            area,
            centre: Point3::from(moment / area),
            normal: normal.normalize(),
        })
        .collect()
}

/// The area two facing triangles on one plane overlap in, and its centroid: `f` clipped by `g`'s edges in `f`'s
/// plane.
fn overlap(f: &Facet, g: &Facet) -> Option<(f64, Point3<f64>)> {
    let seed = if f.normal.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let u = f.normal.cross(&seed).normalize();
    let v = f.normal.cross(&u);
    let origin = f.corners[0];
    let flat = |p: &Point3<f64>| Point2::new((p - origin).dot(&u), (p - origin).dot(&v));
    let mut polygon: Vec<Point2<f64>> = f.corners.iter().map(flat).collect();
    // g faces the other way: its corners run clockwise in f's plane, so each edge is taken reversed
    let clip: Vec<Point2<f64>> = g.corners.iter().rev().map(flat).collect();
    for k in 0..3 {
        let (a, b) = (clip[k], clip[(k + 1) % 3]);
        let inside = |p: &Point2<f64>| (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        let mut next = Vec::with_capacity(polygon.len() + 1);
        for i in 0..polygon.len() {
            let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            let (dp, dq) = (inside(&p), inside(&q));
            if dp >= 0.0 {
                next.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                next.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        polygon = next;
        if polygon.len() < 3 {
            return None;
        }
    }
    // the polygon's area and centroid (the shoelace formula)
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..polygon.len() {
        let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let cross = p.x * q.y - q.x * p.y;
        area += cross;
        cx += (p.x + q.x) * cross;
        cy += (p.y + q.y) * cross;
    }
    if area <= 0.0 {
        return None;
    }
    let (cx, cy) = (cx / (3.0 * area), cy / (3.0 * area));
    Some((area / 2.0, origin + u * cx + v * cy))
}
