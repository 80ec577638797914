//! The wrecking-ball scene: a wall of bricks laid in running bond and glued, and a heavy ball swung into it on a
//! rope.

use crate::body::RigidBodyBuilder;
use crate::collider::Material;
use crate::error::WorldError;
use crate::joint::JointBuilder;
use crate::mode::Mode;
use crate::spring::BodyHandle;
use crate::world::{Fractured, Glue, World};
use nalgebra::{Point3, Vector3};
use tumble_collide::{Mesh, Shape};

/// A brick: 0.3 x 0.2 x 0.15 m.
const BRICK: [f64; 3] = [0.3, 0.2, 0.15];
/// Bricks a course and courses.
const COURSE: usize = 8;
const COURSES: usize = 6;
/// The ball: 110 kg, 0.3 m in radius, on a 3 m rope, meeting the wall at 6 m/s.
const BALL: (f64, f64) = (110.0, 0.3);
const ROPE: f64 = 3.0;
const SPEED: f64 = 6.0;
const G: f64 = 9.81;

/// A wall of 48 bricks (six courses of eight, each course set half a brick along from the one below, so that its
/// ends are toothed) glued at `strength` Pa (117 welds; 30 kN across a brick's end at 1 MPa) averaged over
/// `window` s, standing on the floor (friction 0.7, bricks of 1800 kg/m^3); and a 110 kg ball 0.3 m in radius on
/// a 3 m rope, let go 67 degrees out, that meets the middle of the fourth course's fourth brick at the bottom of
/// its swing at 6 m/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WreckingBall {
    pub strength: f64,
    pub window: f64,
}

impl Default for WreckingBall {
    fn default() -> Self {
        WreckingBall { strength: 1e6, window: crate::world::GLUE_WINDOW }
    }
}

impl WreckingBall {
    /// The world in `mode` (one thread), the wall's pieces and welds, and the ball.
    pub fn build(&self, mode: Mode) -> Result<(World, Fractured, BodyHandle), WorldError> {
        let (wall, bricks) = running_bond_wall()?;
        let mut w = World::new();
        w.set_mode(mode)?;
        w.set_threads(1)?;
        w.add_ground(0.0, Material::new(0.0, 0.7))?;
        let glue = Glue { window: self.window, material: Material::new(0.0, 0.7), ..Glue::new(1800.0, self.strength) };
        let glued = w.add_fractured(&wall, &bricks, &glue)?;
        // the rope hangs above where the ball, at the bottom of its swing, touches the fourth brick of the fourth
        // course (a course laid half a brick along); it is let go from the angle whose drop gives the speed
        let hit = Vector3::new(0.0, -BRICK[1] / 2.0 - BALL.1, 3.5 * BRICK[2]);
        let angle = (1.0 - SPEED * SPEED / (2.0 * G * ROPE)).acos();
        let start = hit + Vector3::new(0.0, -ROPE * angle.sin(), ROPE * (1.0 - angle.cos()));
        let ball = RigidBodyBuilder::from_shape_with_mass(Shape::sphere(BALL.1)?, BALL.0).position(start).name("ball");
        let ball = w.add_body(ball)?;
        w.add_joint(JointBuilder::rope(Some(ball), None, None).anchor_b(hit + Vector3::new(0.0, 0.0, ROPE)))?;
        Ok((w, glued, ball))
    }
}

/// The wall (its frame at the middle of its foot) and its bricks, in courses from the floor up.
pub fn running_bond_wall() -> Result<(Mesh, Vec<Mesh>), WorldError> {
    let [length, depth, height] = BRICK;
    // each course's ends along x: the odd ones half a brick along
    let ends = |j: usize| {
        let a = -(COURSE as f64) * length / 2.0 + if j % 2 == 1 { length / 2.0 } else { 0.0 };
        (a, a + COURSE as f64 * length)
    };
    let (cube, triangles) = Shape::cuboid(Vector3::new(length, depth, height) / 2.0)?.triangle_mesh(1, 1.0);
    let mut bricks = Vec::with_capacity(COURSE * COURSES);
    for j in 0..COURSES {
        for i in 0..COURSE {
            let centre = Vector3::new(ends(j).0 + (i as f64 + 0.5) * length, 0.0, (j as f64 + 0.5) * height);
            let at: Vec<Point3<f64>> = cube.iter().map(|p| p + centre).collect();
            bricks.push(Mesh::new(&at, &triangles, &format!("wall.{:03}", bricks.len()))?);
        }
    }
    // the wall's face: each course a polygon (anticlockwise in x, z), with the corners of the courses above and
    // below on its edges so that the faces meet without T-joints, fanned from its centre
    let mut courses: Vec<Vec<(f64, f64)>> = Vec::with_capacity(COURSES);
    for j in 0..COURSES {
        let ((a, b), (z0, z1)) = (ends(j), (j as f64 * height, (j + 1) as f64 * height));
        let inside = |k: Option<usize>| {
            let mut xs: Vec<f64> = k.map_or(Vec::new(), |k| vec![ends(k).0, ends(k).1]);
            xs.retain(|&x| x > a && x < b);
            xs
        };
        let mut ring = vec![(a, z0)];
        ring.extend(inside(j.checked_sub(1)).into_iter().map(|x| (x, z0)));
        ring.extend([(b, z0), (b, z1)]);
        ring.extend(inside((j + 1 < COURSES).then_some(j + 1)).into_iter().rev().map(|x| (x, z1)));
        ring.push((a, z1));
        courses.push(ring);
    }
    let mut vertices = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut vertex = |x: f64, y: f64, z: f64| {
        vertices.push(Point3::new(x, y, z));
        (vertices.len() - 1) as u32
    };
    let (front, back) = (-depth / 2.0, depth / 2.0);
    for ring in &courses {
        let n = ring.len() as f64;
        let (cx, cz) = ring.iter().fold((0.0, 0.0), |(x, z), p| (x + p.0 / n, z + p.1 / n));
        for (y, flip) in [(front, false), (back, true)] {
            let centre = vertex(cx, y, cz);
            let ids: Vec<u32> = ring.iter().map(|&(x, z)| vertex(x, y, z)).collect();
            for k in 0..ids.len() {
                let (p, q) = (ids[k], ids[(k + 1) % ids.len()]);
                // anticlockwise in (x, z) faces -y: the front; the back the other way
                faces.push(if flip { [centre, q, p] } else { [centre, p, q] });
            }
        }
    }
    // the sides: each edge of a course's polygon that no other course runs back along, as a quad front to back
    let edges: Vec<((f64, f64), (f64, f64))> =
        courses.iter().flat_map(|r| (0..r.len()).map(move |k| (r[k], r[(k + 1) % r.len()]))).collect();
    for &(p, q) in &edges {
        if edges.iter().any(|&(s, t)| s == q && t == p) {
            continue;
        }
        let (pf, qf, pb, qb) =
            (vertex(p.0, front, p.1), vertex(q.0, front, q.1), vertex(p.0, back, p.1), vertex(q.0, back, q.1));
        faces.extend([[pf, qb, qf], [pf, pb, qb]]);
    }
    let wall = Mesh::new(&vertices, &faces, "wall")?;
    Ok((wall, bricks))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mode::FastSettings;

    #[test]
    fn the_wall_is_its_bricks_glued_across_every_end_and_bed() {
        let (wall, bricks) = running_bond_wall().unwrap();
        let brick = BRICK.iter().product::<f64>();
        // a closed solid of 48 bricks' volume (to rounding of sums of a hundred terms)
        assert!((wall.volume() / (48.0 * brick) - 1.0).abs() < 1e-12, "{}", wall.volume());
        assert!(bricks.iter().all(|b| (b.volume() / brick - 1.0).abs() < 1e-12));
        // 7 ends in each of 6 courses and 15 half-brick beds between each of 5 pairs: 117 faces of 0.2 x 0.15 m
        // (an end) or 0.15 x 0.2 m (half a bed), 30 kN at 1 MPa
        let (w, glued, _) = WreckingBall::default().build(Mode::Fast(FastSettings::new(1.0 / 240.0))).unwrap();
        assert_eq!((glued.bodies.len(), glued.bonds.len(), w.joints().count()), (48, 117, 118));
        for (_, face) in &glued.bonds {
            assert!((face.area - BRICK[1] * BRICK[2]).abs() < 1e-12, "{}", face.area);
        }
    }
}
