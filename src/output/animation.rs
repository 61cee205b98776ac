//! A run as an animated glTF 2.0 binary (`.glb`): one node per body carrying its mesh
//! (`model::mesh`), a line on every hinge's fold axis (A0's z axis, fixed in the parent), and
//! one animation whose channels move every body node (translation and rotation, linear) at
//! the recorded times.
//!
//! Frames: glTF is y-up, N is z-up. The scene's one root node, `N (z up)`, turns N into glTF's
//! frame (a −90° rotation about x: N's x stays x, N's z becomes glTF's y, N's y becomes −z);
//! the body nodes are its children with their poses in N, so a body node's translation is its
//! centre of mass `R_i` in N (m) and its rotation the quaternion of `[N i]` (x, y, z, w), read
//! back exactly as the CSV's `{body}_R_*` and `{body}_yaw/pitch/roll` give them (f32).
//!
//! Size: per body per frame, 12 bytes of translation and 16 of rotation; times 4 bytes per
//! frame; meshes once. A 4096-panel run of 1000 frames is ~115 MB.

use crate::math::Vec3;
use crate::model::Model;
use crate::model::mesh::body_mesh;
use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use std::collections::BTreeMap;
use std::path::Path;

/// Bytes per body per frame in the file (translation 3 × f32, rotation 4 × f32).
pub const BYTES_PER_BODY_FRAME: usize = 28;

mod frames;
pub use crate::output::table::Table;
pub use frames::{Frames, frames_from_table};

/// What was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Written {
    /// Frames in the animation.
    pub frames: usize,
    /// File size, bytes.
    pub bytes: usize,
}

/// A palette for panels (linear RGB), the hub grey.
const PALETTE: [[f32; 3]; 6] =
    [[0.85, 0.55, 0.15], [0.2, 0.45, 0.8], [0.3, 0.7, 0.35], [0.75, 0.3, 0.45], [0.55, 0.45, 0.8], [0.9, 0.8, 0.3]];

/// Binary data of the file and its views.
struct Bin {
    data: Vec<u8>,
}

impl Bin {
    /// Appends `bytes` (4-byte values, so every view stays aligned) as a buffer view.
    fn view(
        &mut self,
        root: &mut json::Root,
        bytes: impl Iterator<Item = u8>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.data.len();
        self.data.extend(bytes);
        root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(self.data.len() - offset),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    /// Appends `values` (4-byte aligned) as a view and an accessor of `count` elements of
    /// `type_`; `bounds` adds min and max (required for positions and animation inputs).
    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        root: &mut json::Root,
        values: &[f32],
        type_: json::accessor::Type,
        count: usize,
        target: Option<json::buffer::Target>,
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let view = self.view(root, values.iter().flat_map(|v| v.to_le_bytes()), target);
        let width = values.len() / count.max(1);
        let (min, max) = if bounds {
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for chunk in values.chunks(width) {
                for (k, v) in chunk.iter().enumerate() {
                    lo[k] = lo[k].min(*v);
                    hi[k] = hi[k].max(*v);
                }
            }
            (Some(json::Value::from(lo)), Some(json::Value::from(hi)))
        } else {
            (None, None)
        };
        root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::F32)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn indices(&mut self, root: &mut json::Root, values: &[u32]) -> json::Index<json::Accessor> {
        let view = self.view(
            root,
            values.iter().flat_map(|v| v.to_le_bytes()),
            Some(json::buffer::Target::ElementArrayBuffer),
        );
        root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(values.len()),
            component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::U32)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        })
    }
}

fn material(root: &mut json::Root, name: String, rgb: [f32; 3], two_sided: bool) -> json::Index<json::Material> {
    root.push(json::Material {
        name: Some(name),
        double_sided: two_sided,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([rgb[0], rgb[1], rgb[2], 1.0]),
            metallic_factor: json::material::StrengthFactor(0.1),
            roughness_factor: json::material::StrengthFactor(0.7),
            ..Default::default()
        },
        ..Default::default()
    })
}

fn primitive(
    attributes: Vec<(json::mesh::Semantic, json::Index<json::Accessor>)>,
    indices: Option<json::Index<json::Accessor>>,
    material: json::Index<json::Material>,
    mode: json::mesh::Mode,
) -> json::mesh::Primitive {
    json::mesh::Primitive {
        attributes: attributes.into_iter().map(|(s, a)| (Valid(s), a)).collect::<BTreeMap<_, _>>(),
        extensions: None,
        extras: Default::default(),
        indices,
        material: Some(material),
        mode: Valid(mode),
        targets: None,
    }
}

/// The largest extent of a body's mesh, m.
fn size(positions: &[Vec3]) -> f64 {
    let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
    for p in positions {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (hi - lo).max()
}

/// Writes `frames` of `model` as a glTF binary at `path` (through `path.partial`, renamed
/// when complete).
pub fn write_glb(model: &Model, frames: &Frames, path: &Path) -> Result<Written, String> {
    let glb = glb_bytes(model, frames)?;
    super::paths::write_atomically(path, &glb)?;
    Ok(Written { frames: frames.times.len(), bytes: glb.len() })
}

/// The scale of a body's red copy while it touches: a little larger than the body, so that
/// its faces cover the body's.
const CONTACT_SCALE: f32 = 1.002;

/// Deeper than this a point counts as touching in the animation, m: the frames' poses are
/// single precision (a body 10 m out is placed to ~1e-6 m), so a stack lying face to face
/// at zero gap must not flicker.
pub const CONTACT_SHOWN_DEPTH: f64 = 1e-5;

/// Per body, per frame: whether it touches another body; `None` without contact. From the
/// run's own record when the frames carry it (every accepted step since the frame before,
/// so a touch shorter than a frame shows), else from the frames' poses (see
/// [`Model::touching`]).
fn contact_tracks(model: &Model, frames: &Frames) -> Option<Vec<Vec<bool>>> {
    model.contact.as_ref()?;
    let nb = model.bodies.len();
    let mut tracks = vec![Vec::with_capacity(frames.times.len()); nb];
    if frames.touched.len() == nb * frames.times.len() {
        for f in 0..frames.times.len() {
            for (b, track) in tracks.iter_mut().enumerate() {
                track.push(frames.touched[f * nb + b]);
            }
        }
        return Some(tracks);
    }
    for f in 0..frames.times.len() {
        let poses: Vec<(Vec3, crate::math::Mat3)> = (0..nb)
            .map(|b| {
                let t = frames.translations[f * nb + b];
                let [x, y, z, w] = frames.rotations[f * nb + b];
                let q = [w as f64, x as f64, y as f64, z as f64];
                (Vec3::new(t[0] as f64, t[1] as f64, t[2] as f64), crate::math::dcm_from_quat(&q))
            })
            .collect();
        for (track, t) in tracks.iter_mut().zip(model.touching(&poses, CONTACT_SHOWN_DEPTH)) {
            track.push(t);
        }
    }
    Some(tracks)
}

/// The glTF binary of `frames` of `model`.
pub fn glb_bytes(model: &Model, frames: &Frames) -> Result<Vec<u8>, String> {
    if frames.times.is_empty() || frames.bodies != model.bodies.len() {
        return Err("no frames to animate".into());
    }
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("foldsim {}", env!("CARGO_PKG_VERSION"))),
            version: "2.0".into(),
            copyright: None,
            extensions: None,
            extras: Default::default(),
            min_version: None,
        },
        ..Default::default()
    };
    let mut bin = Bin { data: Vec::new() };
    let meshes: Vec<_> = model.bodies.iter().map(body_mesh).collect();
    let sizes: Vec<f64> = meshes.iter().map(|m| size(&m.positions)).collect();
    let mut body_nodes = Vec::new();
    // With contact: per body a copy of its mesh in red, shown (scale 1) while it touches
    // another body and hidden (scale 0) otherwise.
    let mut contact_nodes: Vec<json::Index<json::Node>> = Vec::new();
    let touching = contact_tracks(model, frames);
    let mut children: Vec<Vec<json::Index<json::Node>>> = vec![Vec::new(); model.bodies.len()];
    // Hinge lines: half the smaller body's size, on A0's z axis through its origin.
    let line_material = material(&mut root, "hinge lines".into(), [0.05, 0.05, 0.05], false);
    for h in &model.hinges {
        let half = 0.25 * sizes[h.parent].min(sizes[h.child]).max(1e-3);
        let axis = h.dcm_a0_parent.transpose() * Vec3::z();
        let ends = [h.r_a0_in_parent - half * axis, h.r_a0_in_parent + half * axis];
        let values: Vec<f32> = ends.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]).collect();
        let positions = bin.accessor(
            &mut root,
            &values,
            json::accessor::Type::Vec3,
            2,
            Some(json::buffer::Target::ArrayBuffer),
            true,
        );
        let mesh = root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(format!("{} axis", h.name)),
            primitives: vec![primitive(
                vec![(json::mesh::Semantic::Positions, positions)],
                None,
                line_material,
                json::mesh::Mode::Lines,
            )],
            weights: None,
        });
        let node =
            root.push(json::Node { mesh: Some(mesh), name: Some(format!("{} axis", h.name)), ..Default::default() });
        children[h.parent].push(node);
    }
    for (b, (body, mesh)) in model.bodies.iter().zip(&meshes).enumerate() {
        let rgb = if b == 0 { [0.55, 0.55, 0.6] } else { PALETTE[(b - 1) % PALETTE.len()] };
        let mat = material(&mut root, body.name.clone(), rgb, mesh.two_sided);
        let flat = |v: &[Vec3]| -> Vec<f32> { v.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]).collect() };
        let count = mesh.positions.len();
        let positions = bin.accessor(
            &mut root,
            &flat(&mesh.positions),
            json::accessor::Type::Vec3,
            count,
            Some(json::buffer::Target::ArrayBuffer),
            true,
        );
        let normals = bin.accessor(
            &mut root,
            &flat(&mesh.normals),
            json::accessor::Type::Vec3,
            count,
            Some(json::buffer::Target::ArrayBuffer),
            false,
        );
        let index_values: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let indices = bin.indices(&mut root, &index_values);
        let gl_mesh = root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(body.name.clone()),
            primitives: vec![primitive(
                vec![(json::mesh::Semantic::Positions, positions), (json::mesh::Semantic::Normals, normals)],
                Some(indices),
                mat,
                json::mesh::Mode::Triangles,
            )],
            weights: None,
        });
        if let Some(tracks) = &touching {
            let red = material(&mut root, format!("{} in contact", body.name), [0.9, 0.08, 0.05], mesh.two_sided);
            let red_mesh = root.push(json::Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(format!("{} in contact", body.name)),
                primitives: vec![primitive(
                    vec![(json::mesh::Semantic::Positions, positions), (json::mesh::Semantic::Normals, normals)],
                    Some(indices),
                    red,
                    json::mesh::Mode::Triangles,
                )],
                weights: None,
            });
            let shown = if tracks[b][0] { CONTACT_SCALE } else { 0.0 };
            let node = root.push(json::Node {
                mesh: Some(red_mesh),
                name: Some(format!("{} in contact", body.name)),
                scale: Some([shown; 3]),
                ..Default::default()
            });
            children[b].push(node);
            contact_nodes.push(node);
        }
        let node = root.push(json::Node {
            mesh: Some(gl_mesh),
            name: Some(body.name.clone()),
            translation: Some(frames.translations[b]),
            rotation: Some(json::scene::UnitQuaternion(frames.rotations[b])),
            children: if children[b].is_empty() { None } else { Some(children[b].clone()) },
            ..Default::default()
        });
        body_nodes.push(node);
    }
    let n_frame = root.push(json::Node {
        name: Some("N (z up)".into()),
        rotation: Some(json::scene::UnitQuaternion([
            -std::f32::consts::FRAC_1_SQRT_2,
            0.0,
            0.0,
            std::f32::consts::FRAC_1_SQRT_2,
        ])),
        children: Some(body_nodes.clone()),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some("foldsim run".into()),
        nodes: vec![n_frame],
    });
    root.scene = Some(scene);

    // The animation: times, then per body its translations and rotations.
    let times: Vec<f32> = frames.times.iter().map(|&t| t as f32).collect();
    if times.windows(2).any(|w| w[1] <= w[0]) {
        return Err("frame times must increase in single precision; choose a lower frame rate".into());
    }
    let input = bin.accessor(&mut root, &times, json::accessor::Type::Scalar, times.len(), None, true);
    let mut channels = Vec::new();
    let mut samplers = Vec::new();
    for (b, node) in body_nodes.iter().enumerate() {
        let nb = model.bodies.len();
        let translations: Vec<f32> = frames.translations.iter().skip(b).step_by(nb).flatten().copied().collect();
        let mut previous = [0.0f32, 0.0, 0.0, 1.0];
        let rotations: Vec<f32> = frames
            .rotations
            .iter()
            .skip(b)
            .step_by(nb)
            .flat_map(|&q| {
                let mut q = q;
                // The same rotation on the same side of the 4-D sphere as the last frame.
                if q.iter().zip(&previous).map(|(a, b)| a * b).sum::<f32>() < 0.0 {
                    q = q.map(|x| -x);
                }
                previous = q;
                q
            })
            .collect();
        for (values, path, type_) in [
            (translations, json::animation::Property::Translation, json::accessor::Type::Vec3),
            (rotations, json::animation::Property::Rotation, json::accessor::Type::Vec4),
        ] {
            let output = bin.accessor(&mut root, &values, type_, times.len(), None, false);
            let linear = json::animation::Interpolation::Linear;
            channel(&mut samplers, &mut channels, (input, output, linear), *node, path);
        }
    }
    // Contact: each body's red copy scaled 1 (a little more, to cover it) while it touches
    // and 0 otherwise, stepwise.
    if let Some(tracks) = &touching {
        for (track, node) in tracks.iter().zip(&contact_nodes) {
            let values: Vec<f32> = track.iter().flat_map(|&t| [if t { CONTACT_SCALE } else { 0.0 }; 3]).collect();
            let output = bin.accessor(&mut root, &values, json::accessor::Type::Vec3, times.len(), None, false);
            let step = json::animation::Interpolation::Step;
            channel(&mut samplers, &mut channels, (input, output, step), *node, json::animation::Property::Scale);
        }
    }
    root.push(json::Animation {
        extensions: None,
        extras: Default::default(),
        channels,
        name: Some("run".into()),
        samplers,
    });
    root.push(json::Buffer {
        byte_length: USize64::from(bin.data.len()),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    Ok(glb_container(&root.to_vec().map_err(|e| format!("cannot encode the glTF JSON: {e}"))?, &bin.data))
}

/// Adds an animation channel driving `path` of `node` by a sampler over (input times,
/// output values, interpolation).
fn channel(
    samplers: &mut Vec<json::animation::Sampler>,
    channels: &mut Vec<json::animation::Channel>,
    (input, output, interpolation): (
        json::Index<json::Accessor>,
        json::Index<json::Accessor>,
        json::animation::Interpolation,
    ),
    node: json::Index<json::Node>,
    path: json::animation::Property,
) {
    let sampler = json::Index::new(samplers.len() as u32);
    samplers.push(json::animation::Sampler {
        extensions: None,
        extras: Default::default(),
        input,
        interpolation: Valid(interpolation),
        output,
    });
    channels.push(json::animation::Channel {
        sampler,
        target: json::animation::Target { extensions: None, extras: Default::default(), node, path: Valid(path) },
        extensions: None,
        extras: Default::default(),
    });
}

/// A quaternion (w, x, y, z) as glTF's (x, y, z, w) in f32, normalized after rounding.
fn rotation_f32(q: &[f64; 4]) -> [f32; 4] {
    let v = [q[1] as f32, q[2] as f32, q[3] as f32, q[0] as f32];
    let n = v.iter().map(|x| x * x).sum::<f32>().sqrt();
    v.map(|x| x / n)
}

/// The GLB container: a 12-byte header, the JSON chunk (padded with spaces) and the binary
/// chunk (padded with zeros), each length a multiple of 4 (glTF 2.0 §4.4).
fn glb_container(json_bytes: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| n.div_ceil(4) * 4;
    let (json_len, bin_len) = (pad(json_bytes.len()), pad(bin.len()));
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json_bytes);
    out.resize(12 + 8 + json_len, b' ');
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}

/// The animation read back from a file written by [`write_glb`]: times, and per body node
/// (by name) its translations and rotations (x, y, z, w) per frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadBack {
    /// Frame times, s.
    pub times: Vec<f32>,
    /// Per animated node: name, translations, rotations.
    pub nodes: Vec<NodeTrack>,
}

/// One node's animation: its name, translations (m, N) and rotations (x, y, z, w) per frame.
pub type NodeTrack = (String, Vec<[f32; 3]>, Vec<[f32; 4]>);

/// Reads the animation of a `.glb` written by [`write_glb`].
pub fn read_glb(path: &Path) -> Result<ReadBack, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let bad = |what: &str| format!("{}: {what}", path.display());
    if bytes.len() < 20 || &bytes[0..4] != b"glTF" {
        return Err(bad("not a glTF binary"));
    }
    let word = |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as usize;
    let json_len = word(12);
    let root: json::Root =
        serde_json::from_slice(&bytes[20..20 + json_len]).map_err(|e| bad(&format!("its JSON: {e}")))?;
    let bin = &bytes[20 + json_len + 8..];
    let floats = |a: json::Index<json::Accessor>| -> Vec<f32> {
        let acc = &root.accessors[a.value()];
        let view = &root.buffer_views[acc.buffer_view.expect("a view").value()];
        let start = view.byte_offset.map_or(0, |o| o.0 as usize);
        bin[start..start + view.byte_length.0 as usize]
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    };
    let animation = root.animations.first().ok_or_else(|| bad("no animation"))?;
    let mut out = ReadBack::default();
    for pair in animation.channels.chunks(2) {
        let node = &root.nodes[pair[0].target.node.value()];
        let sampler = |c: &json::animation::Channel| &animation.samplers[c.sampler.value()];
        out.times = floats(sampler(&pair[0]).input);
        let t = floats(sampler(&pair[0]).output);
        let r = floats(sampler(&pair[1]).output);
        out.nodes.push((
            node.name.clone().unwrap_or_default(),
            t.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
            r.chunks(4).map(|c| [c[0], c[1], c[2], c[3]]).collect(),
        ));
    }
    Ok(out)
}
