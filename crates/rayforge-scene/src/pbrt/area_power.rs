//! An area light's `power` on a mesh, as pbrt-v4 gives it.
//!
//! pbrt-v4 makes one `DiffuseAreaLight` for each shape an `AreaLightSource` applies to, and a
//! triangle mesh is one shape per triangle (`scene.cpp`, `CreateLights`: a light for each of
//! `Shape::Create`'s shapes). Each light scales its radiance so that it alone emits `power`
//! (`lights.cpp`, `DiffuseAreaLight::Create`: `scale *= power / (sides · π · area)`, the area
//! that of the one triangle, in render space): a mesh's triangles of unequal areas shine with
//! unequal radiances, each emitting `power`, the mesh N × `power` in all. A `bilinearmesh`
//! is one shape per patch (pbrt-v4's `BilinearPatch`), which rayforge tessellates: each
//! patch's triangles share the patch's area (their sum, the patch's own for a planar patch
//! and within the tessellation's bound of it for a curved one), so the patch emits `power`.
//!
//! rayforge's emission is a material's, one per object, so an emitting mesh with `power` is
//! cut into [`pieces`]: its faces grouped by their area in the world (areas within a millionth
//! of each other alike, as rounding makes a regular grid's), each group a mesh of its own with
//! the group's mean area, which keeps the group's power exactly. Past `max_radiances` groups (`PbrtLimits::radiances`, `--max-pbrt-radiances`, 1024 by default)
//! (a mesh of many sizes: a scanned lamp), the faces are grouped instead into that many bands
//! of equal ratio between the smallest and largest area; each band still emits its faces'
//! power, and a face's radiance is off pbrt-v4's by at most the band's spread of areas, which
//! [`Pieces::spread`] reports for a warning.

use super::reader::Entity;
use crate::error::SceneError;
use glam::DMat4;
use rayforge::geometry::{Mesh, MeshError, MeshFace, VertexAttributes};

/// Areas closer than this fraction of each other count as one size.
const SAME_SIZE: f64 = 1e-6;

/// An emitting mesh cut by the area of its faces.
pub struct Pieces {
    /// Each piece's mesh and its faces' mean area in the world (0 for degenerate faces,
    /// which no ray meets and which emit nothing).
    pub pieces: Vec<(Mesh, f64)>,
    /// When the faces had more than `max_radiances` sizes: the largest ratio between the
    /// areas of two faces sharing a radiance.
    pub spread: Option<f64>,
}

/// Whether the area light gives `power` (pbrt-v4 takes a value above 0 only).
pub fn has_power(area_light: &Entity) -> Result<bool, SceneError> {
    Ok(area_light.params.float("power")?.is_some_and(|p| p > 0.0))
}

/// The mesh `mesh` (in its object's space, placed by `world_from_object`) cut into pieces of
/// faces of one area each (see the [module](self)); with `patches`, how many of its faces in
/// order each of pbrt-v4's shapes is (a `bilinearmesh`'s patches), a face's area is its
/// shape's; at most `max_radiances` pieces, degenerate faces' included (and at least one
/// band of sized faces).
pub fn pieces(
    mesh: &Mesh,
    world_from_object: &DMat4,
    patches: Option<&[u32]>,
    max_radiances: usize,
) -> Result<Pieces, MeshError> {
    let mut areas: Vec<f64> = mesh
        .faces()
        .map(|face| {
            let [a, b, c] = mesh
                .corners(&face)
                .map(|p| world_from_object.transform_point3(p));
            (b - a).cross(c - a).length() / 2.0
        })
        .collect();
    if let Some(patches) = patches {
        let mut start = 0;
        for &n in patches {
            let end = (start + n as usize).min(areas.len());
            let total: f64 = areas[start..end].iter().sum();
            areas[start..end].fill(total);
            start = end;
        }
    }
    let (groups, spread) = groups(&areas, max_radiances);
    let mut remap = Remaps::default();
    let pieces = groups
        .iter()
        .map(|faces| {
            let total: f64 = faces.iter().map(|&f| areas[f as usize]).sum();
            let mean = total / faces.len() as f64;
            Ok((sub_mesh(mesh, faces, &mut remap)?, mean))
        })
        .collect::<Result<Vec<_>, MeshError>>()?;
    Ok(Pieces { pieces, spread })
}

/// The faces (indices into `areas`) grouped by area: degenerate faces (area 0) first, then
/// one group per size, in increasing area; past `max` groups, `max` bands of equal ratio, and
/// the largest ratio of areas within one of them.
fn groups(areas: &[f64], max: usize) -> (Vec<Vec<u32>>, Option<f64>) {
    let mut order: Vec<u32> = (0..areas.len() as u32).collect();
    order.sort_by(|&a, &b| areas[a as usize].total_cmp(&areas[b as usize]));
    let flat = order.partition_point(|&f| areas[f as usize] <= 0.0);
    let (flat, sized) = order.split_at(flat);
    let mut groups: Vec<Vec<u32>> = Vec::new();
    if !flat.is_empty() {
        groups.push(flat.to_vec());
    }
    let mut sizes: Vec<Vec<u32>> = Vec::new();
    let mut first = f64::NAN;
    for &f in sized {
        let a = areas[f as usize];
        match sizes.last_mut() {
            Some(group) if a <= first * (1.0 + SAME_SIZE) => group.push(f),
            _ => {
                first = a;
                sizes.push(vec![f]);
            }
        }
    }
    if sizes.len() <= max.saturating_sub(groups.len()) {
        groups.extend(sizes);
        return (groups, None);
    }
    // Bands of equal ratio from the smallest area to the largest.
    let bands = max.saturating_sub(groups.len()).max(1);
    let (least, most) = (
        areas[sized[0] as usize],
        areas[sized[sized.len() - 1] as usize],
    );
    let step = (most / least).ln() / bands as f64;
    let mut banded: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for &f in sized {
        let band = ((areas[f as usize] / least).ln() / step) as usize;
        banded[band.min(bands - 1)].push(f);
    }
    banded.retain(|b| !b.is_empty());
    let spread = banded
        .iter()
        .map(|b| areas[b[b.len() - 1] as usize] / areas[b[0] as usize])
        .fold(1.0, f64::max);
    groups.extend(banded);
    (groups, Some(spread))
}

/// Old index to new, for one list of a mesh's vertex data, reused from piece to piece (only
/// the entries a piece set are cleared after it, so a mesh of many pieces costs its size once).
#[derive(Default)]
struct Remap {
    new: Vec<u32>,
    used: Vec<u32>,
}

impl Remap {
    const UNSET: u32 = u32::MAX;

    /// Starts a piece over a list of `len` entries.
    fn start(&mut self, len: usize) {
        for &old in &self.used {
            self.new[old as usize] = Self::UNSET;
        }
        self.used.clear();
        self.new.resize(len, Self::UNSET);
    }

    /// The new index of `old`, given the next one when first seen.
    fn index(&mut self, old: u32) -> u32 {
        let slot = &mut self.new[old as usize];
        if *slot == Self::UNSET {
            *slot = self.used.len() as u32;
            self.used.push(old);
        }
        *slot
    }

    /// The entries of `list` the piece uses, in their new order.
    fn taken<T: Copy>(&self, list: &[T]) -> Vec<T> {
        self.used.iter().map(|&i| list[i as usize]).collect()
    }
}

/// One [`Remap`] for each list a face indexes.
#[derive(Default)]
struct Remaps {
    positions: Remap,
    normals: Remap,
    texcoords: Remap,
}

/// The mesh of `faces` of `mesh`, holding only the vertex data they use, wound as `mesh` is.
fn sub_mesh(mesh: &Mesh, faces: &[u32], remap: &mut Remaps) -> Result<Mesh, MeshError> {
    remap.positions.start(mesh.positions().len());
    remap.normals.start(mesh.normals().len());
    remap.texcoords.start(mesh.texcoords().len());
    let picked: Vec<MeshFace> = faces
        .iter()
        .map(|&f| {
            let face = mesh.face(f as usize);
            MeshFace {
                vertices: face.vertices.map(|i| remap.positions.index(i)),
                normals: face.normals.map(|n| n.map(|i| remap.normals.index(i))),
                texcoords: face.texcoords.map(|t| t.map(|i| remap.texcoords.index(i))),
            }
        })
        .collect();
    let piece = Mesh::with_texcoords(
        remap.positions.taken(mesh.positions()),
        remap.normals.taken(mesh.normals()),
        remap.texcoords.taken(mesh.texcoords()),
        picked,
    )?
    .with_winding(mesh.winding());
    Ok(match mesh.attributes() {
        // Tangents and colours are indexed as the positions are.
        Some(a) => piece
            .with_attributes(VertexAttributes {
                tangents: if a.tangents.is_empty() {
                    Vec::new()
                } else {
                    remap.positions.taken(&a.tangents)
                },
                colors: if a.colors.is_empty() {
                    Vec::new()
                } else {
                    remap.positions.taken(&a.colors)
                },
            })
            .expect("one tangent and colour a kept position"),
        None => piece,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn faces_of_one_size_share_a_group_and_degenerate_ones_stand_apart() {
        // Rounding makes a grid's equal areas differ in the last bits: one size.
        let areas = [2.0, 0.5, 2.0 * (1.0 + 1e-12), 0.0, 0.5, 8.0];
        let (groups, spread) = groups(&areas, crate::pbrt::PbrtLimits::DEFAULT.radiances);
        assert_eq!(spread, None);
        assert_eq!(groups, vec![vec![3], vec![1, 4], vec![0, 2], vec![5]]);
    }

    #[test]
    fn past_the_cap_bands_of_equal_ratio_keep_each_face_near_its_own_radiance() {
        // 5000 sizes from 1 to 1000: 64 bands of ratio 1000^(1/64) ≈ 1.114.
        let areas: Vec<f64> = (0..5000).map(|i| 1000f64.powf(i as f64 / 4999.0)).collect();
        let (groups, spread) = groups(&areas, 64);
        assert!(groups.len() <= 64 && groups.len() > 60, "{}", groups.len());
        let spread = spread.expect("banded");
        let ratio = 1000f64.powf(1.0 / 64.0);
        assert!(
            spread <= ratio * (1.0 + 1e-9) && spread > 1.0,
            "{spread} {ratio}"
        );
        // Every face in exactly one band, and within its band's spread of each other.
        let mut all: Vec<u32> = groups.concat();
        all.sort_unstable();
        assert_eq!(all, (0..5000).collect::<Vec<u32>>());
        for g in &groups {
            let (lo, hi) = g.iter().fold((f64::MAX, 0f64), |(lo, hi), &f| {
                (lo.min(areas[f as usize]), hi.max(areas[f as usize]))
            });
            assert!(hi / lo <= spread * (1.0 + 1e-12));
        }
    }

    #[test]
    fn the_pieces_hold_the_mesh_faces_with_their_own_vertex_data() {
        // Two triangles of areas 0.5 and 1 (in the world, scaled by 2: 2 and 4), sharing an
        // edge, with normals and texture coordinates.
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-2.0, 0.0, 0.0),
        ];
        let normals = vec![DVec3::Z; 4];
        let texcoords = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.5]];
        let face = |v: [u32; 3]| MeshFace {
            vertices: v,
            normals: Some(v),
            texcoords: Some(v),
        };
        let mesh = Mesh::with_texcoords(
            positions,
            normals,
            texcoords,
            vec![face([0, 1, 2]), face([3, 0, 2])],
        )
        .unwrap()
        .with_winding(rayforge::geometry::Winding::RightHanded);
        let Pieces { pieces, spread } =
            pieces(&mesh, &DMat4::from_scale(DVec3::splat(2.0)), None, 1024).unwrap();
        assert_eq!(spread, None);
        assert_eq!(pieces.len(), 2);
        let (small, area) = &pieces[0];
        assert!((area - 2.0).abs() < 1e-12, "{area}");
        assert_eq!(small.face_count(), 1);
        assert_eq!(small.positions().len(), 3);
        assert_eq!(small.corners(&small.face(0)), mesh.corners(&mesh.face(0)));
        assert_eq!(small.winding(), rayforge::geometry::Winding::RightHanded);
        let (large, area) = &pieces[1];
        assert!((area - 4.0).abs() < 1e-12, "{area}");
        assert_eq!(large.corners(&large.face(0)), mesh.corners(&mesh.face(1)));
        let t = large.face(0).texcoords.unwrap();
        assert_eq!(large.texcoords()[t[0] as usize], [0.5, 0.5]);
        assert_eq!(large.normals().len(), 3);
    }
}
