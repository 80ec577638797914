//! Closed meshes read from files, with the file's units and up axis stated: OBJ (tobj), STL (stl_io), PLY
//! (ply-rs-bw) and glTF/GLB (gltf), each mesh of a glTF placed by its node's transforms. A file's meshes come one by
//! one (`Mesh::load_all`) or merged into one (`Mesh::load`).

use crate::error::ShapeError;
use crate::surface_mesh::Mesh;
use nalgebra::{Matrix4, Point3};
use std::path::Path;

/// Which axis of the file points up (tumble's up is +z).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// +y up (glTF's convention, and many modelling tools'): turned +90 degrees about x, so y goes to z.
    Y,
    /// +z up (Blender's, and tumble's): kept.
    Z,
    /// The format's own: +y for glTF and GLB (their specification says so), +z (the coordinates as given) for OBJ,
    /// STL and PLY, which state none.
    OfFormat,
}

impl UpAxis {
    /// "y" or "z".
    pub fn named(name: &str) -> Result<UpAxis, ShapeError> {
        match name {
            "y" | "Y" => Ok(UpAxis::Y),
            "z" | "Z" => Ok(UpAxis::Z),
            other => Err(ShapeError::new("up", format!("must be \"y\" or \"z\", got \"{other}\""))),
        }
    }

    /// The axis itself for a file of extension `ext` (lower case): `OfFormat` made y or z.
    fn for_format(self, ext: &str) -> UpAxis {
        match (self, ext) {
            (UpAxis::OfFormat, "gltf" | "glb") => UpAxis::Y,
            (UpAxis::OfFormat, _) => UpAxis::Z,
            (up, _) => up,
        }
    }
}

/// One mesh of a file before it is checked: name, vertices (file frame, file units) and triangles.
struct Raw {
    name: String,
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The meshes of a file, each scaled by `scale` (file units to metres) and turned so that `up` is +z.
    pub fn load_all(path: impl AsRef<Path>, scale: f64, up: UpAxis) -> Result<Vec<Mesh>, ShapeError> {
        let path = path.as_ref();
        if !(scale.is_finite() && scale > 0.0) {
            return Err(ShapeError::new("scale", format!("must be finite and > 0, got {scale}")));
        }
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let raws = match ext.as_str() {
            "obj" => obj(path)?,
            "stl" => stl(path)?,
            "ply" => ply(path)?,
            "gltf" | "glb" => gltf(path)?,
            other => {
                return Err(ShapeError::new(
                    "path",
                    format!(
                        "{}: unknown mesh format \".{other}\" (OBJ, STL, PLY, glTF and GLB are read)",
                        path.display()
                    ),
                ))
            }
        };
        if raws.is_empty() {
            return Err(ShapeError::new("path", format!("{}: the file has no triangles", path.display())));
        }
        let up = up.for_format(&ext);
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        let mut unnamed = 0;
        raws.into_iter()
            .map(|r| {
                let v: Vec<Point3<f64>> = r.vertices.iter().map(|p| turned(p, up) * scale).collect();
                let name = if placeholder(&r.name) {
                    unnamed += 1;
                    if unnamed == 1 {
                        stem.to_string()
                    } else {
                        format!("{stem}.{:03}", unnamed - 1)
                    }
                } else {
                    r.name
                };
                Mesh::new(&v, &r.triangles, &name)
            })
            .collect()
    }

    /// A file's meshes merged into one (each placed as the file places it), scaled and turned as `load_all`, named
    /// after the file. Meshes whose solids overlap are refused (merged, the volume they share would count twice in
    /// the mass): `load_all` gives them one by one.
    pub fn load(path: impl AsRef<Path>, scale: f64, up: UpAxis) -> Result<Mesh, ShapeError> {
        let path = path.as_ref();
        let mut all = Self::load_all(path, scale, up)?;
        if all.len() == 1 {
            return Ok(all.remove(0));
        }
        for (i, a) in all.iter().enumerate() {
            if let Some(b) = all[i + 1..].iter().find(|b| crate::mesh_overlap::solids_overlap(a, b)) {
                return Err(ShapeError::new(
                    "path",
                    format!(
                        "{}: its meshes \"{}\" and \"{}\" overlap: merged into one, the volume they share would count \
                         twice in the mass; load them one by one with Mesh.load_all (as one body's colliders, or \
                         bodies of their own), or join them into one solid first",
                        path.display(),
                        a.name(),
                        b.name()
                    ),
                ));
            }
        }
        let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
        for m in &all {
            let base = vertices.len() as u32;
            vertices.extend_from_slice(m.vertices());
            triangles.extend(m.triangles().iter().map(|t| t.map(|k| k + base)));
        }
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        Mesh::new(&vertices, &triangles, name).map_err(|e| {
            ShapeError::new(
                "path",
                format!(
                    "{}: its {} meshes merged do not bound one solid ({}): load them one by one with \
                     Mesh.load_all, or join them into one solid first",
                    path.display(),
                    all.len(),
                    e.reason
                ),
            )
        })
    }
}

/// Whether a file's name for a mesh is one its writer made up rather than the user's (tobj's for an OBJ without
/// object names, trimesh's for the meshes of a glTF it writes, or none): the mesh is then named after the file.
fn placeholder(name: &str) -> bool {
    let numbered = |prefix: &str| name.strip_prefix(prefix).is_some_and(|n| n.chars().all(|c| c.is_ascii_digit()));
    name.is_empty() || name == "unnamed_object" || numbered("geometry_")
}

/// A file's point turned so that `up` (y or z, as `for_format` leaves it) is +z.
fn turned(p: &Point3<f64>, up: UpAxis) -> Point3<f64> {
    match up {
        UpAxis::Y => Point3::new(p.x, -p.z, p.y),
        UpAxis::Z | UpAxis::OfFormat => *p,
    }
}

fn unreadable(path: &Path, what: impl std::fmt::Display) -> ShapeError {
    ShapeError::new("path", format!("{}: {what}", path.display()))
}

fn obj(path: &Path) -> Result<Vec<Raw>, ShapeError> {
    let options = tobj::LoadOptions { triangulate: true, single_index: false, ..Default::default() };
    let (models, _) = tobj::load_obj(path, &options).map_err(|e| unreadable(path, e))?;
    Ok(models
        .into_iter()
        .filter(|m| !m.mesh.indices.is_empty())
        .map(|m| Raw {
            name: m.name,
            vertices: m.mesh.positions.chunks_exact(3).map(|c| Point3::new(c[0], c[1], c[2])).collect(),
            triangles: m.mesh.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        })
        .collect())
}

fn stl(path: &Path) -> Result<Vec<Raw>, ShapeError> {
    let mut file = std::fs::File::open(path).map_err(|e| unreadable(path, e))?;
    let mesh = stl_io::read_stl(&mut file).map_err(|e| unreadable(path, e))?;
    let index = |k: usize| u32::try_from(k).map_err(|_| unreadable(path, "more than 2^32 vertices"));
    let triangles = mesh
        .faces
        .iter()
        .map(|f| Ok([index(f.vertices[0])?, index(f.vertices[1])?, index(f.vertices[2])?]))
        .collect::<Result<Vec<_>, ShapeError>>()?;
    let vertices = mesh.vertices.iter().map(|v| Point3::new(v[0] as f64, v[1] as f64, v[2] as f64)).collect();
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("").to_string();
    Ok(if triangles.is_empty() { vec![] } else { vec![Raw { name, vertices, triangles }] })
}

fn ply(path: &Path) -> Result<Vec<Raw>, ShapeError> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut file = std::fs::File::open(path).map_err(|e| unreadable(path, e))?;
    let ply = Parser::<DefaultElement>::new().read_ply(&mut file).map_err(|e| unreadable(path, e))?;
    let number = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Float(v) => *v as f64,
            Property::Double(v) => *v,
            Property::Int(v) => *v as f64,
            Property::UInt(v) => *v as f64,
            Property::Short(v) => *v as f64,
            Property::UShort(v) => *v as f64,
            Property::Char(v) => *v as f64,
            Property::UChar(v) => *v as f64,
            _ => return None,
        })
    };
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| unreadable(path, "no \"vertex\" element"))?
        .iter()
        .map(|v| match (number(v.get("x")), number(v.get("y")), number(v.get("z"))) {
            (Some(x), Some(y), Some(z)) => Ok(Point3::new(x, y, z)),
            _ => Err(unreadable(path, "a vertex without numeric x, y and z")),
        })
        .collect::<Result<Vec<_>, ShapeError>>()?;
    let mut triangles = Vec::new();
    for (i, f) in ply.payload.get("face").map(|f| f.as_slice()).unwrap_or(&[]).iter().enumerate() {
        let list = f.get("vertex_indices").or_else(|| f.get("vertex_index"));
        let ids: Vec<i64> = match list {
            Some(Property::ListInt(l)) => l.iter().map(|&k| k as i64).collect(),
            Some(Property::ListUInt(l)) => l.iter().map(|&k| k as i64).collect(),
            Some(Property::ListShort(l)) => l.iter().map(|&k| k as i64).collect(),
            Some(Property::ListUShort(l)) => l.iter().map(|&k| k as i64).collect(),
            Some(Property::ListUChar(l)) => l.iter().map(|&k| k as i64).collect(),
            Some(Property::ListChar(l)) => l.iter().map(|&k| k as i64).collect(),
            _ => return Err(unreadable(path, format!("face {i} has no integer vertex_indices"))),
        };
        let ids = ids
            .iter()
            .map(|&k| u32::try_from(k).map_err(|_| unreadable(path, format!("face {i} has vertex index {k}"))))
            .collect::<Result<Vec<u32>, ShapeError>>()?;
        // a polygon as a fan from its first vertex
        for k in 1..ids.len().saturating_sub(1) {
            triangles.push([ids[0], ids[k], ids[k + 1]]);
        }
    }
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("").to_string();
    Ok(if triangles.is_empty() { vec![] } else { vec![Raw { name, vertices, triangles }] })
}

fn gltf(path: &Path) -> Result<Vec<Raw>, ShapeError> {
    let (doc, buffers, _) = gltf::import(path).map_err(|e| unreadable(path, e))?;
    let mut out = Vec::new();
    let scenes: Vec<gltf::Scene> = match doc.default_scene() {
        Some(s) => vec![s],
        None => doc.scenes().collect(),
    };
    let mut stack: Vec<(gltf::Node, Matrix4<f64>, usize)> =
        scenes.iter().flat_map(|s| s.nodes()).map(|n| (n, Matrix4::identity(), 0)).collect();
    stack.reverse();
    // a node hierarchy is a forest: deeper than there are nodes means a cycle
    let nodes = doc.nodes().len();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > nodes {
            return Err(unreadable(path, "its node hierarchy has a cycle"));
        }
        let m = node.transform().matrix();
        let local = Matrix4::from_fn(|r, c| m[c][r] as f64);
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            let mut raw = Raw {
                name: node.name().or(mesh.name()).unwrap_or("").to_string(),
                vertices: Vec::new(),
                triangles: Vec::new(),
            };
            for prim in mesh.primitives().filter(|p| p.mode() == gltf::mesh::Mode::Triangles) {
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let Some(positions) = reader.read_positions() else { continue };
                let base = raw.vertices.len() as u32;
                let start = raw.vertices.len();
                raw.vertices.extend(positions.map(|p| {
                    let q = world.transform_point(&Point3::new(p[0] as f64, p[1] as f64, p[2] as f64));
                    Point3::new(q.x, q.y, q.z)
                }));
                let count = (raw.vertices.len() - start) as u32;
                let ids: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..count).collect(),
                };
                raw.triangles.extend(ids.chunks_exact(3).map(|c| [c[0] + base, c[1] + base, c[2] + base]));
            }
            // a mirroring transform turns the winding inside out: put it back
            if world.fixed_view::<3, 3>(0, 0).determinant() < 0.0 {
                raw.triangles.iter_mut().for_each(|t| t.swap(1, 2));
            }
            if !raw.triangles.is_empty() {
                out.push(raw);
            }
        }
        let children: Vec<_> = node.children().collect();
        for child in children.into_iter().rev() {
            stack.push((child, world, depth + 1));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::UpAxis;

    #[test]
    fn by_default_the_format_decides_which_axis_is_up() {
        for ext in ["gltf", "glb"] {
            assert_eq!(UpAxis::OfFormat.for_format(ext), UpAxis::Y, "glTF is +y up by its specification");
            assert_eq!(UpAxis::Z.for_format(ext), UpAxis::Z, "a stated axis wins");
        }
        for ext in ["obj", "stl", "ply"] {
            assert_eq!(UpAxis::OfFormat.for_format(ext), UpAxis::Z, "as given");
            assert_eq!(UpAxis::Y.for_format(ext), UpAxis::Y);
        }
    }
}
