//! The stylised humanoid: lofted body parts that overlap into one figure, cut along its
//! material boundaries (`outfit`), smooth skin weights and per-vertex thickness.

use super::cut::cut;
use super::mesh::Mesh;
use super::outfit::{self, Mat};
use super::shapes::Tube;
use super::skeleton::*;
use super::texture::atlas;
use glam::Vec3;

/// A body part: its surface and the bones (with a reach factor) that may influence it.
struct Part {
    tube: Tube,
    bones: Vec<(usize, f32)>,
}

pub struct Character {
    pub mesh: Mesh,
    pub joints: Vec<[u8; 4]>,
    pub weights: Vec<[f32; 4]>,
    /// Local thickness through each vertex along its inward normal (metres).
    pub thickness: Vec<f32>,
    /// The material of each triangle.
    pub materials: Vec<Mat>,
    pub skeleton: Vec<Joint>,
}

#[allow(clippy::too_many_arguments)]
fn tube(
    start: Vec3,
    end: Vec3,
    side: Vec3,
    profile: &[[f32; 4]],
    offset_dir: Vec3,
    caps: [f32; 2],
    res: [usize; 3],
    uv: [f32; 4],
) -> Tube {
    Tube {
        start,
        end,
        side,
        profile: profile.to_vec(),
        offset_dir,
        caps,
        squareness: 0.0,
        segments: res[0],
        body_rings: res[1],
        cap_rings: res[2],
        uv_rect: uv,
    }
}

fn parts() -> Vec<Part> {
    let mut p = Vec::new();
    let y = Vec3::Y;
    let (x, z) = (Vec3::X, Vec3::Z);
    // Torso: crotch to shoulders, slightly boxy.
    let mut torso = tube(
        Vec3::new(0.0, 0.80, -0.005),
        Vec3::new(0.0, 1.49, -0.02),
        x,
        &[
            [0.00, 0.120, 0.095, 0.0],
            [0.14, 0.165, 0.112, 0.0],
            [0.30, 0.155, 0.104, 0.0],
            [0.45, 0.136, 0.096, 0.004],
            [0.62, 0.152, 0.108, 0.012],
            [0.80, 0.168, 0.104, 0.008],
            [0.92, 0.176, 0.090, 0.0],
            [1.00, 0.150, 0.075, 0.0],
        ],
        z,
        [0.12, 0.13],
        [32, 16, 6],
        atlas::TORSO,
    );
    torso.squareness = 0.35;
    p.push(Part {
        tube: torso,
        bones: vec![
            (HIPS, 1.0),
            (SPINE, 1.0),
            (CHEST, 1.0),
            (NECK, 0.8),
            (ARM_L + SHOULDER, 0.85),
            (ARM_R + SHOULDER, 0.85),
            (LEG_L + UPPER_LEG, 0.7),
            (LEG_R + UPPER_LEG, 0.7),
        ],
    });
    p.push(Part {
        tube: tube(
            Vec3::new(0.0, 1.39, -0.02),
            Vec3::new(0.0, 1.60, -0.01),
            x,
            &[
                [0.0, 0.056, 0.052, 0.0],
                [0.5, 0.047, 0.047, 0.0],
                [1.0, 0.05, 0.05, 0.0],
            ],
            z,
            [0.12, 0.12],
            [20, 6, 3],
            atlas::NECK,
        ),
        bones: vec![(CHEST, 0.8), (NECK, 1.0), (HEAD, 0.9)],
    });
    p.push(Part {
        tube: tube(
            Vec3::new(0.0, 1.515, 0.0),
            Vec3::new(0.0, 1.755, -0.01),
            x,
            &[
                [0.00, 0.045, 0.050, 0.025],
                [0.15, 0.062, 0.070, 0.012],
                [0.40, 0.076, 0.092, 0.0],
                [0.60, 0.080, 0.098, -0.004],
                [0.80, 0.076, 0.092, -0.006],
                [1.00, 0.064, 0.076, -0.006],
            ],
            z,
            [0.18, 0.35],
            [32, 10, 7],
            atlas::HEAD,
        ),
        bones: vec![(HEAD, 1.0)],
    });
    // Nose.
    p.push(Part {
        tube: tube(
            Vec3::new(0.0, 1.640, 0.078),
            Vec3::new(0.0, 1.592, 0.106),
            x,
            &[
                [0.0, 0.009, 0.010, 0.0],
                [0.7, 0.012, 0.012, 0.0],
                [1.0, 0.013, 0.011, 0.0],
            ],
            z,
            [0.4, 0.35],
            [12, 3, 4],
            atlas::NOSE,
        ),
        bones: vec![(HEAD, 1.0)],
    });
    for s in [1.0f32, -1.0] {
        let mx = |v: Vec3| Vec3::new(v.x * s, v.y, v.z);
        let arm = if s > 0.0 { ARM_L } else { ARM_R };
        let leg = if s > 0.0 { LEG_L } else { LEG_R };
        let d = arm_dir(s);
        // Ear: a thin ellipsoid, flat across X.
        p.push(Part {
            tube: tube(
                mx(Vec3::new(0.078, 1.583, 0.004)),
                mx(Vec3::new(0.083, 1.655, -0.012)),
                z,
                &[
                    [0.0, 0.016, 0.0048, 0.0],
                    [0.6, 0.020, 0.0052, 0.0],
                    [1.0, 0.018, 0.005, 0.0],
                ],
                x,
                [0.5, 0.5],
                [12, 2, 5],
                atlas::EAR,
            ),
            bones: vec![(HEAD, 1.0)],
        });
        // Whole arm in one tube (straight in the bind pose), so the elbow has no seam.
        p.push(Part {
            tube: tube(
                upper_arm_pos(s) - d * 0.05,
                wrist_pos(s) + d * 0.012,
                z,
                &[
                    [0.0, 0.052, 0.050, 0.0],
                    [0.25, 0.046, 0.043, 0.0],
                    [0.50, 0.038, 0.036, 0.0],
                    [0.557, 0.036, 0.034, 0.0],
                    [0.64, 0.038, 0.034, 0.0],
                    [1.0, 0.028, 0.021, 0.0],
                ],
                z,
                [0.08, 0.05],
                [18, 18, 4],
                atlas::ARM,
            ),
            bones: vec![
                (arm + SHOULDER, 0.8),
                (arm + UPPER_ARM, 1.0),
                (arm + LOWER_ARM, 1.0),
                (arm + HAND, 0.9),
            ],
        });
        // Hand: palm, four fingers, thumb. The palm faces the thigh.
        let w = wrist_pos(s);
        let palm_n = Vec3::new(-0.788 * s, -0.616, 0.0);
        p.push(Part {
            tube: tube(
                w - d * 0.012,
                w + d * 0.098,
                z,
                &[
                    [0.0, 0.030, 0.018, 0.0],
                    [0.5, 0.041, 0.017, 0.0],
                    [1.0, 0.042, 0.014, 0.0],
                ],
                z,
                [0.25, 0.2],
                [16, 4, 4],
                atlas::PALM,
            ),
            bones: vec![(arm + LOWER_ARM, 0.8), (arm + HAND, 1.0)],
        });
        let fingers = [
            (0.027, 0.074),
            (0.009, 0.082),
            (-0.009, 0.078),
            (-0.026, 0.062),
        ];
        for (off, len) in fingers {
            let start = w + d * 0.082 + z * off;
            let dir = (d + palm_n * 0.18).normalize();
            p.push(Part {
                tube: tube(
                    start,
                    start + dir * len,
                    z,
                    &[[0.0, 0.0068, 0.0064, 0.0], [1.0, 0.0058, 0.0054, 0.0]],
                    z,
                    [0.1, 0.1],
                    [8, 4, 3],
                    atlas::FINGER,
                ),
                bones: vec![(arm + HAND, 1.0)],
            });
        }
        let tstart = w + d * 0.02 + z * 0.028 + palm_n * 0.006;
        let tdir = (d * 0.55 + z * 0.6 + palm_n * 0.35).normalize();
        p.push(Part {
            tube: tube(
                tstart,
                tstart + tdir * 0.07,
                z,
                &[
                    [0.0, 0.0095, 0.0085, 0.0],
                    [0.5, 0.0085, 0.0075, 0.0],
                    [1.0, 0.0068, 0.0062, 0.0],
                ],
                z,
                [0.12, 0.1],
                [8, 4, 3],
                atlas::FINGER,
            ),
            bones: vec![(arm + HAND, 1.0)],
        });
        // Whole leg in one tube (straight in the bind pose), so the knee has no seam.
        p.push(Part {
            tube: tube(
                hip_pos(s) + y * 0.06,
                ankle_pos(s) - y * 0.015,
                z,
                &[
                    [0.0, 0.080, 0.084, 0.0],
                    [0.16, 0.080, 0.083, 0.0],
                    [0.37, 0.064, 0.066, 0.0],
                    [0.50, 0.050, 0.052, 0.004],
                    [0.53, 0.049, 0.051, 0.004],
                    [0.62, 0.054, 0.058, -0.010],
                    [0.85, 0.037, 0.039, -0.003],
                    [1.0, 0.032, 0.034, 0.0],
                ],
                z,
                [0.05, 0.05],
                [20, 22, 4],
                atlas::LEG,
            ),
            bones: vec![
                (HIPS, 0.8),
                (leg + UPPER_LEG, 1.0),
                (leg + LOWER_LEG, 1.0),
                (leg + FOOT, 0.9),
            ],
        });
        p.push(Part {
            tube: tube(
                mx(Vec3::new(0.09, 0.044, -0.065)),
                mx(Vec3::new(0.092, 0.026, 0.185)),
                x,
                &[
                    [0.0, 0.034, 0.040, 0.0],
                    [0.35, 0.040, 0.050, 0.012],
                    [0.75, 0.044, 0.030, 0.002],
                    [1.0, 0.040, 0.022, 0.0],
                ],
                y,
                [0.16, 0.14],
                [16, 7, 5],
                atlas::FOOT,
            ),
            bones: vec![(leg + LOWER_LEG, 0.8), (leg + FOOT, 1.0)],
        });
    }
    p
}

fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (p - (a + ab * t)).length()
}

/// Up to four influences by inverse sixth power of the (reach-scaled) distance to each bone segment.
fn skin_vertex(p: Vec3, bones: &[(usize, f32)], sk: &[Joint]) -> ([u8; 4], [f32; 4]) {
    let mut inf: Vec<(usize, f32)> = bones
        .iter()
        .map(|&(b, reach)| {
            let d = segment_distance(p, sk[b].pos, sk[b].tail).max(0.004) / reach;
            let w = 1.0 / (d * d * d * d * d * d);
            (b, w)
        })
        .collect();
    // Stable order: weight descending, ties by joint index.
    inf.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    inf.truncate(4);
    let total: f32 = inf.iter().map(|x| x.1).sum();
    let mut j = [0u8; 4];
    let mut w = [0f32; 4];
    for (k, &(b, wt)) in inf.iter().enumerate() {
        let v = wt / total;
        // Drop negligible influences so they do not cost a skinning fetch.
        if v >= 0.01 {
            j[k] = b as u8;
            w[k] = v;
        }
    }
    let sum: f32 = w.iter().sum();
    for x in &mut w {
        *x /= sum;
    }
    // Unused slots must reference joint 0 with weight 0.
    for k in 0..4 {
        if w[k] == 0.0 {
            j[k] = 0;
        }
    }
    (j, w)
}

/// The eyeballs: flattened ellipsoids looking along +z, set into the head so 3 mm show.
fn eyes(head: &Mesh) -> Vec<Part> {
    let (rx, ry, rz) = (0.014, 0.009, 0.010);
    let protrude = 0.003;
    [1.0f32, -1.0]
        .into_iter()
        .map(|s| {
            let (x, y) = (0.032 * s, 1.624);
            let from = 0.3;
            let surface = head
                .ray_hit(Vec3::new(x, y, from), -Vec3::Z, 0.0)
                .map_or(0.085, |d| from - d);
            let c = Vec3::new(x, y, surface + protrude - rz);
            let r = [rx, ry, 0.0];
            Part {
                tube: tube(
                    c - Vec3::Z * rz,
                    c + Vec3::Z * rz,
                    Vec3::X,
                    &[[0.0, r[0], r[1], r[2]], [1.0, r[0], r[1], r[2]]],
                    Vec3::X,
                    [0.45, 0.45],
                    [16, 1, 6],
                    atlas::EYE,
                ),
                bones: vec![(HEAD, 1.0)],
            }
        })
        .collect()
}

pub fn build() -> Character {
    let skeleton = joints();
    let mut mesh = Mesh::default();
    let mut joints4 = Vec::new();
    let mut weights = Vec::new();
    let mut thickness = Vec::new();
    let mut materials = Vec::new();
    let mut parts = parts();
    let head = parts
        .iter()
        .find(|p| p.tube.uv_rect == atlas::HEAD)
        .map(|p| p.tube.build_with_diameters().0)
        .unwrap_or_default();
    parts.extend(eyes(&head));
    for part in parts {
        let rect = part.tube.uv_rect;
        let (mut m, mut diam) = part.tube.build_with_diameters();
        for field in outfit::boundaries(rect) {
            let (cut_mesh, origins) = cut(&m, field);
            for (a, b, t) in origins {
                let (da, db) = (diam[a as usize], diam[b as usize]);
                diam.push(da + (db - da) * t);
            }
            m = cut_mesh;
        }
        for t in m.indices.chunks(3) {
            let tri = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            materials.push(outfit::triangle_material(tri, rect));
        }
        for ((p, n), diam) in m.positions.iter().zip(&m.normals).zip(diam) {
            let (j, w) = skin_vertex(*p, &part.bones, &skeleton);
            joints4.push(j);
            weights.push(w);
            // Chord through the part along the inward normal, but never more than the part's
            // cross-section: at rounded ends the axial chord (a whole limb) is no SSS depth.
            let eps = 1.0e-4;
            let chord = m
                .ray_hit(*p - *n * eps, -*n, 1.0e-5)
                .map(|d| d + eps)
                .unwrap_or(diam);
            thickness.push(chord.min(diam).clamp(0.004, 0.30));
        }
        mesh.append(&m);
    }
    Character {
        mesh,
        joints: joints4,
        weights,
        thickness,
        materials,
        skeleton,
    }
}

/// One primitive of the character: the triangles of one material, with their own vertices.
pub struct Primitive {
    pub material: Mat,
    pub mesh: Mesh,
    pub joints: Vec<[u8; 4]>,
    pub weights: Vec<[f32; 4]>,
    pub thickness: Vec<f32>,
}

impl Character {
    /// One primitive per material present, in [`Mat::ALL`] order (vertices in first-use order).
    pub fn primitives(&self) -> Vec<Primitive> {
        let mut out = Vec::new();
        for mat in Mat::ALL {
            let mut remap = vec![u32::MAX; self.mesh.vertex_count()];
            let mut p = Primitive {
                material: mat,
                mesh: Mesh::default(),
                joints: Vec::new(),
                weights: Vec::new(),
                thickness: Vec::new(),
            };
            let m = &self.mesh;
            for (t, _) in m
                .indices
                .chunks(3)
                .zip(&self.materials)
                .filter(|(_, &x)| x == mat)
            {
                for &i in t {
                    let i = i as usize;
                    if remap[i] == u32::MAX {
                        remap[i] = p.mesh.positions.len() as u32;
                        p.mesh.positions.push(m.positions[i]);
                        p.mesh.normals.push(m.normals[i]);
                        p.mesh.uvs.push(m.uvs[i]);
                        p.mesh.tangents.push(m.tangents[i]);
                        p.joints.push(self.joints[i]);
                        p.weights.push(self.weights[i]);
                        p.thickness.push(self.thickness[i]);
                    }
                    p.mesh.indices.push(remap[i]);
                }
            }
            if !p.mesh.indices.is_empty() {
                out.push(p);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportions_and_weights() {
        let c = build();
        let (lo, hi) = c.mesh.bounds();
        assert!(lo.y.abs() < 0.01, "feet at y=0: {lo}");
        assert!((hi.y - 1.75).abs() < 0.03, "height: {hi}");
        for w in &c.weights {
            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5);
        }
        let thin = c.thickness.iter().cloned().fold(f32::INFINITY, f32::min);
        let thick = c.thickness.iter().cloned().fold(0.0, f32::max);
        assert!(thin < 0.013 && thick > 0.2, "{thin} {thick}");
    }

    #[test]
    fn every_material_is_a_primitive_of_its_own() {
        let c = build();
        let prims = c.primitives();
        let mats: Vec<Mat> = prims.iter().map(|p| p.material).collect();
        assert_eq!(mats, Mat::ALL);
        let tris: usize = prims.iter().map(|p| p.mesh.triangle_count()).sum();
        assert_eq!(tris, c.mesh.triangle_count());
        for p in &prims {
            let n = p.mesh.vertex_count();
            assert!(p.mesh.indices.iter().all(|&i| (i as usize) < n));
            assert_eq!(
                (p.joints.len(), p.weights.len(), p.thickness.len()),
                (n, n, n)
            );
        }
        // Skin is most of the figure; the eyes are two small eyeballs.
        let count = |m: Mat| {
            prims
                .iter()
                .find(|p| p.material == m)
                .unwrap()
                .mesh
                .triangle_count()
        };
        assert!(count(Mat::Skin) > count(Mat::TankTop) && count(Mat::Eyes) < 1000);
    }
}
