//! Floor maps as glTF 2.0 binary models (`.glb`).
//!
//! # Frame
//! glTF is Y-up, right-handed, in metres (or camera heights when the map has no scale). A map
//! point `(x, y, z)` (x right, y forward, z up) becomes the glTF point `(x, z, -y)`: a proper
//! rotation of -90° about x, so forward is glTF's `-Z` (the direction glTF cameras look) and
//! triangle windings and volumes are preserved.
//!
//! # Contents
//! One scene with flat, un-transformed nodes, each with its own mesh:
//! - `floor`: the floor outline as a flat, ear-cut mesh facing up; a rectangle around the objects
//!   and the station point when the map has no floor outline (then named
//!   `floor (bounding rectangle)`).
//! - one node per object, named exactly like the object: a closed prism of the object's height
//!   (sides, top and bottom caps, outward windings). Objects without a height (or a non-positive
//!   one) get a nominal height of 1% of the map's size; their mesh name ends in
//!   `(nominal height)` and the node's extras say `"height_known": false`.
//! - `camera`: a small pyramid with its apex at the camera centre `(0, 0, height)`, looking
//!   forward and down by the pitch and turned about its viewing axis by the roll (a positive
//!   roll, the horizon falling to the right in the photo, lifts the camera's right side), as
//!   wide as the horizontal field of view.
//!
//! Normals are flat (each face has its own vertices), indices are `u32`, materials are one per
//! category (floor grey, boxes blue, footprints orange, camera red), all data lives in the GLB's
//! binary chunk.

use std::collections::BTreeMap;

use gltf_json::accessor::{ComponentType, GenericComponentType, Type};
use gltf_json::buffer::{Target, View};
use gltf_json::material::{PbrBaseColorFactor, PbrMetallicRoughness, StrengthFactor};
use gltf_json::mesh::{Mode, Primitive, Semantic};
use gltf_json::validation::{Checked::Valid, USize64};
use gltf_json::{Accessor, Buffer, Index, Material, Mesh, Node, Root, Scene};
use serde_json::json;
use vpmap_metrology::map::{CameraReport, FloorMap, MapPoint, Units};
use vpmap_metrology::reconstruct::ObjectKind;

use crate::error::RenderError;
use crate::geometry::{Bounds, clean_ring, signed_area, triangulate};

/// Nominal height of objects without one, as a fraction of the map's larger side.
pub const NOMINAL_HEIGHT_FRAC: f64 = 0.01;
/// Depth of the camera pyramid, as a fraction of the camera height.
const CAMERA_DEPTH_FRAC: f64 = 0.3;
/// Largest field-of-view half angle drawn, degrees (wider would make the pyramid flat).
const MAX_HALF_FOV_DEG: f64 = 80.0;
/// Border of the fallback floor rectangle, as a fraction of the map's larger side.
const FLOOR_RECT_MARGIN_FRAC: f64 = 0.1;

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const GLB_VERSION: u32 = 2;
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"

/// A map point `(x, y, z)` in glTF coordinates `(x, z, -y)`, in `f32`.
fn gltf_from_map(p: [f64; 3]) -> [f32; 3] {
    // `0.0 - y` rather than `-y`: no negative zeros in the file.
    [p[0] as f32, p[2] as f32, (0.0 - p[1]) as f32]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalised(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    if n > 0.0 && n.is_finite() {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Triangles of one mesh, flat-shaded, in glTF coordinates.
#[derive(Debug, Default)]
struct MeshData {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    indices: Vec<u32>,
}

impl MeshData {
    /// Add a planar face: its corners (map frame), triangles indexing them (counter-clockwise
    /// seen from the side `normal` points to) and its normal (map frame).
    fn add_face(&mut self, corners: &[[f64; 3]], triangles: &[[usize; 3]], normal: [f64; 3]) {
        let base = self.positions.len() as u32;
        let n = gltf_from_map(normalised(normal));
        for c in corners {
            self.positions.push(gltf_from_map(*c));
            self.normals.push(n);
        }
        for t in triangles {
            self.indices.extend(t.iter().map(|&i| base + i as u32));
        }
    }

    /// Add one triangle of a convex solid, wound to face away from `inside`.
    fn add_outward_triangle(&mut self, tri: [[f64; 3]; 3], inside: [f64; 3]) {
        let [a, b, c] = tri;
        let normal = cross(sub(b, a), sub(c, a));
        let centre = [
            (a[0] + b[0] + c[0]) / 3.0,
            (a[1] + b[1] + c[1]) / 3.0,
            (a[2] + b[2] + c[2]) / 3.0,
        ];
        if dot(normal, sub(centre, inside)) >= 0.0 {
            self.add_face(&tri, &[[0, 1, 2]], normal);
        } else {
            self.add_face(
                &[a, c, b],
                &[[0, 1, 2]],
                [-normal[0], -normal[1], -normal[2]],
            );
        }
    }
}

/// A closed prism over a counter-clockwise ring: sides, top cap, bottom cap.
fn prism(ring: &[MapPoint], caps: &[[usize; 3]], height: f64) -> MeshData {
    let mut mesh = MeshData::default();
    let next = ring.iter().cycle().skip(1);
    for (a, b) in ring.iter().zip(next) {
        let corners = [
            [a[0], a[1], 0.0],
            [b[0], b[1], 0.0],
            [b[0], b[1], height],
            [a[0], a[1], height],
        ];
        // Outward for a counter-clockwise ring: the edge direction turned clockwise.
        let normal = [b[1] - a[1], a[0] - b[0], 0.0];
        mesh.add_face(&corners, &[[0, 1, 2], [0, 2, 3]], normal);
    }
    let top: Vec<[f64; 3]> = ring.iter().map(|p| [p[0], p[1], height]).collect();
    mesh.add_face(&top, caps, [0.0, 0.0, 1.0]);
    let bottom: Vec<[f64; 3]> = ring.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let reversed: Vec<[usize; 3]> = caps.iter().map(|t| [t[0], t[2], t[1]]).collect();
    mesh.add_face(&bottom, &reversed, [0.0, 0.0, -1.0]);
    mesh
}

/// Check that a value is finite and fits in `f32`.
fn check(field: impl FnOnce() -> String, value: f64) -> Result<f64, RenderError> {
    if !value.is_finite() {
        return Err(RenderError::NonFinite {
            field: field(),
            value,
        });
    }
    if value.abs() > f64::from(f32::MAX) {
        return Err(RenderError::OutOfRange {
            field: field(),
            value,
        });
    }
    Ok(value)
}

/// Check every coordinate of a ring.
fn check_ring(field: &str, ring: &[MapPoint]) -> Result<(), RenderError> {
    for (i, p) in ring.iter().enumerate() {
        for (k, v) in p.iter().enumerate() {
            check(|| format!("{field}[{i}][{k}]"), *v)?;
        }
    }
    Ok(())
}

/// A cleaned, counter-clockwise ring and its cap triangles, or `None` when it has no area.
fn solid_ring(ring: &[MapPoint], what: &str) -> Result<Option<CcwRing>, RenderError> {
    let mut ring = clean_ring(ring);
    let area = signed_area(&ring);
    if ring.len() < 3 || area == 0.0 {
        return Ok(None);
    }
    if area < 0.0 {
        ring.reverse();
    }
    let triangles = triangulate(&ring).map_err(|reason| RenderError::Triangulation {
        what: what.to_owned(),
        corners: ring.len(),
        reason,
    })?;
    Ok(Some(CcwRing { ring, triangles }))
}

/// A counter-clockwise ring with its triangulation.
struct CcwRing {
    ring: Vec<MapPoint>,
    triangles: Vec<[usize; 3]>,
}

/// Glue between the meshes and the glTF document: one buffer, views and accessors per mesh.
struct Writer {
    root: Root,
    bin: Vec<u8>,
    materials: BTreeMap<&'static str, Index<Material>>,
}

impl Writer {
    fn new() -> Self {
        let mut root = Root::default();
        root.asset.generator = Some(format!("vpmap-render {}", env!("CARGO_PKG_VERSION")));
        Self {
            root,
            bin: Vec::new(),
            materials: BTreeMap::new(),
        }
    }

    /// The material of a category, created on first use.
    fn material(&mut self, category: &'static str, rgba: [f32; 4]) -> Index<Material> {
        if let Some(m) = self.materials.get(category) {
            return *m;
        }
        let m = self.root.push(Material {
            name: Some(category.to_owned()),
            pbr_metallic_roughness: PbrMetallicRoughness {
                base_color_factor: PbrBaseColorFactor(rgba),
                metallic_factor: StrengthFactor(0.0),
                roughness_factor: StrengthFactor(0.9),
                ..PbrMetallicRoughness::default()
            },
            ..Material::default()
        });
        self.materials.insert(category, m);
        m
    }

    /// Append bytes as a buffer view (4-byte aligned).
    fn view(&mut self, bytes: &[u8], target: Target) -> Index<View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(View {
            buffer: Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: None,
        })
    }

    fn accessor(
        &mut self,
        view: Index<View>,
        count: usize,
        component: ComponentType,
        type_: Type,
        bounds: Option<([f32; 3], [f32; 3])>,
    ) -> Index<Accessor> {
        let as_json = |v: [f32; 3]| json!(v.map(f64::from));
        self.root.push(Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Valid(type_),
            min: bounds.map(|b| as_json(b.0)),
            max: bounds.map(|b| as_json(b.1)),
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// Add a mesh and a node holding it; returns the node.
    fn node(
        &mut self,
        name: &str,
        mesh_name: &str,
        mesh: &MeshData,
        material: Index<Material>,
        extras: &serde_json::Value,
    ) -> Index<Node> {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &mesh.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let floats = |v: &[[f32; 3]]| -> Vec<u8> {
            v.iter()
                .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
                .collect()
        };
        let ints: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let n = mesh.positions.len();
        let view = self.view(&floats(&mesh.positions), Target::ArrayBuffer);
        let positions = self.accessor(view, n, ComponentType::F32, Type::Vec3, Some((lo, hi)));
        let view = self.view(&floats(&mesh.normals), Target::ArrayBuffer);
        let normals = self.accessor(view, n, ComponentType::F32, Type::Vec3, None);
        let view = self.view(&ints, Target::ElementArrayBuffer);
        let indices = self.accessor(
            view,
            mesh.indices.len(),
            ComponentType::U32,
            Type::Scalar,
            None,
        );
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(Semantic::Positions), positions);
        attributes.insert(Valid(Semantic::Normals), normals);
        let mesh = self.root.push(Mesh {
            extensions: None,
            extras: None,
            name: Some(mesh_name.to_owned()),
            primitives: vec![Primitive {
                attributes,
                extensions: None,
                extras: None,
                indices: Some(indices),
                material: Some(material),
                mode: Valid(Mode::Triangles),
                targets: None,
            }],
            weights: None,
        });
        self.root.push(Node {
            mesh: Some(mesh),
            name: Some(name.to_owned()),
            extras: serde_json::value::to_raw_value(extras).ok(),
            ..Node::default()
        })
    }

    /// The finished GLB: header, JSON chunk (space-padded), BIN chunk (zero-padded).
    fn finish(
        mut self,
        nodes: Vec<Index<Node>>,
        extras: &serde_json::Value,
    ) -> Result<Vec<u8>, RenderError> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let bin_len = u32::try_from(self.bin.len()).map_err(|_| RenderError::TooLarge {
            bytes: self.bin.len() as u64,
        })?;
        self.root.push(Buffer {
            byte_length: USize64::from(u64::from(bin_len)),
            name: None,
            uri: None,
            extensions: None,
            extras: None,
        });
        let scene = self.root.push(Scene {
            extensions: None,
            extras: serde_json::value::to_raw_value(extras).ok(),
            name: Some("vpmap floor map".to_owned()),
            nodes,
        });
        self.root.scene = Some(scene);
        let mut json =
            serde_json::to_vec(&self.root).map_err(|e| RenderError::Json(e.to_string()))?;
        while json.len() % 4 != 0 {
            json.push(b' ');
        }
        let total = 12 + 8 + json.len() as u64 + 8 + u64::from(bin_len);
        let total_u32 = u32::try_from(total).map_err(|_| RenderError::TooLarge { bytes: total })?;
        let json_len = json.len() as u32;
        let mut out = Vec::with_capacity(total as usize);
        for word in [GLB_MAGIC, GLB_VERSION, total_u32, json_len, CHUNK_JSON] {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(&json);
        for word in [bin_len, CHUNK_BIN] {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(&self.bin);
        Ok(out)
    }
}

fn units_name(units: Units) -> &'static str {
    match units {
        Units::Meters => "m",
        Units::CameraHeights => "camera_heights",
    }
}

/// The camera's axes in the map frame: `(right, up, forward)`. Pitched down by `pitch_deg`
/// about `x`, then turned about the viewing direction by `roll_deg` (positive: the horizon
/// falls to the right in the image, so the camera's right side is tilted up). Non-finite
/// angles count as 0.
fn camera_axes(pitch_deg: f64, roll_deg: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let radians = |deg: f64| {
        if deg.is_finite() {
            deg.to_radians()
        } else {
            0.0
        }
    };
    let (sp, cp) = radians(pitch_deg).sin_cos();
    let (sr, cr) = radians(roll_deg).sin_cos();
    let forward = [0.0, cp, -sp];
    let up0 = [0.0, sp, cp];
    let right = [cr, sr * up0[1], sr * up0[2]];
    let up = [-sr, cr * up0[1], cr * up0[2]];
    (right, up, forward)
}

/// The camera pyramid's apex and base corners (map frame): apex at the camera centre, base
/// `depth` ahead along the viewing direction, spanning the horizontal field of view and the
/// image's aspect; corners bottom-left, bottom-right, top-right, top-left in the image.
///
/// A room's camera stands at its `position` and is turned by its `heading_deg`.
fn camera_frustum(camera: &CameraReport, height: f64, depth: f64) -> ([f64; 3], [[f64; 3]; 4]) {
    let [left, right] = camera.horizontal_fov_deg.map(|a| {
        if a.is_finite() {
            a.clamp(-MAX_HALF_FOV_DEG, MAX_HALF_FOV_DEG)
                .to_radians()
                .tan()
        } else {
            0.0
        }
    });
    let (left, right) = if right - left > 1e-3 {
        (left, right)
    } else {
        (-0.577, 0.577)
    };
    let image = camera.image;
    let aspect = if image.width > 0 && image.height > 0 {
        f64::from(image.height) / f64::from(image.width)
    } else {
        0.75
    };
    let half_v = (right - left) / 2.0 * aspect;
    let placed = camera.heading_deg.is_some();
    let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
    let apex = if placed {
        [
            finite(camera.position[0]),
            finite(camera.position[1]),
            height,
        ]
    } else {
        [0.0, 0.0, height]
    };
    let (s, c) = finite(camera.heading_deg.unwrap_or(0.0))
        .to_radians()
        .sin_cos();
    let turn = |a: [f64; 3]| [c * a[0] - s * a[1], s * a[0] + c * a[1], a[2]];
    let (right_axis, up, forward) = camera_axes(camera.pitch_deg, camera.roll_deg);
    let (right_axis, up, forward) = (turn(right_axis), turn(up), turn(forward));
    let corner = |h: f64, v: f64| -> [f64; 3] {
        std::array::from_fn(|k| apex[k] + depth * (forward[k] + h * right_axis[k] + v * up[k]))
    };
    let base = [
        corner(left, -half_v),
        corner(right, -half_v),
        corner(right, half_v),
        corner(left, half_v),
    ];
    (apex, base)
}

/// The camera pyramid of [`camera_frustum`] as a closed mesh with outward faces.
fn camera_pyramid(camera: &CameraReport, height: f64, depth: f64) -> MeshData {
    let (apex, base) = camera_frustum(camera, height, depth);
    let inside = [
        (apex[0] + base.iter().map(|c| c[0]).sum::<f64>()) / 5.0,
        (apex[1] + base.iter().map(|c| c[1]).sum::<f64>()) / 5.0,
        (apex[2] + base.iter().map(|c| c[2]).sum::<f64>()) / 5.0,
    ];
    let mut mesh = MeshData::default();
    for i in 0..4 {
        mesh.add_outward_triangle([apex, base[i], base[(i + 1) % 4]], inside);
    }
    mesh.add_outward_triangle([base[0], base[1], base[2]], inside);
    mesh.add_outward_triangle([base[0], base[2], base[3]], inside);
    mesh
}

/// Build a glTF 2.0 binary (`.glb`) model of a floor map: the floor, each object as a solid of
/// its height, and the camera. See the [module docs](self) for the frame `(x, z, -y)` and the
/// contents.
///
/// # Errors
/// [`RenderError::NonFinite`] or [`RenderError::OutOfRange`] for a coordinate or height that is
/// not a finite `f32`; [`RenderError::DegenerateFootprint`] for an object without area;
/// [`RenderError::Triangulation`] when a polygon cannot be triangulated;
/// [`RenderError::TooLarge`] beyond 4 GiB.
///
/// # Example
/// ```
/// use vpmap_metrology::map::{build_map, BuildOptions};
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
/// let map = build_map(&scene, &BuildOptions::default()).unwrap();
/// let glb = vpmap_render::model_glb(&map).unwrap();
/// assert_eq!(&glb[0..4], b"glTF");
/// assert_eq!(u32::from_le_bytes([glb[8], glb[9], glb[10], glb[11]]) as usize, glb.len());
/// ```
///
/// # Complexity
/// `O(n²)` worst case for a polygon of `n` corners (ear cutting), linear in practice.
pub fn model_glb(map: &FloorMap) -> Result<Vec<u8>, RenderError> {
    let camera_height = check(|| "camera.height".to_owned(), map.camera.height)?;
    check_ring("floor", &map.floor)?;
    for (i, o) in map.objects.iter().enumerate() {
        check_ring(&format!("objects[{i}].footprint"), &o.footprint)?;
        if let Some(h) = o.height {
            check(|| format!("objects[{i}].height"), h)?;
        }
    }
    let bounds = Bounds::of_map(map);
    let size = bounds.size_or(if camera_height > 0.0 {
        camera_height
    } else {
        1.0
    });
    let units = units_name(map.units);
    let mut w = Writer::new();
    let mut nodes = Vec::with_capacity(map.objects.len() + 2);

    // Floor.
    let floor = solid_ring(&map.floor, "the floor")?;
    let (floor, floor_name) = if let Some(f) = floor {
        (f, "floor")
    } else {
        let r = bounds.padded(FLOOR_RECT_MARGIN_FRAC * size);
        let ring = [r.min, [r.max[0], r.min[1]], r.max, [r.min[0], r.max[1]]];
        let fallback = solid_ring(&ring, "the floor rectangle")?.ok_or_else(|| {
            RenderError::Triangulation {
                what: "the floor rectangle".to_owned(),
                corners: 4,
                reason: format!("it has no area (size {size})"),
            }
        })?;
        (fallback, "floor (bounding rectangle)")
    };
    let mut mesh = MeshData::default();
    let corners: Vec<[f64; 3]> = floor.ring.iter().map(|p| [p[0], p[1], 0.0]).collect();
    mesh.add_face(&corners, &floor.triangles, [0.0, 0.0, 1.0]);
    let material = w.material("floor", [0.72, 0.72, 0.72, 1.0]);
    let extras = json!({ "outline_given": floor_name == "floor", "units": units });
    nodes.push(w.node(floor_name, floor_name, &mesh, material, &extras));

    // Objects.
    let nominal = NOMINAL_HEIGHT_FRAC * size;
    for (i, o) in map.objects.iter().enumerate() {
        let what = format!("object {i} \"{}\"", o.name);
        let clean = clean_ring(&o.footprint);
        let Some(solid) = solid_ring(&o.footprint, &what)? else {
            return Err(RenderError::DegenerateFootprint {
                name: o.name.clone(),
                corners: clean.len(),
                area: signed_area(&clean).abs(),
            });
        };
        let (height, known) = match o.height {
            Some(h) if h > 0.0 => (h, true),
            _ => (nominal, false),
        };
        let mesh = prism(&solid.ring, &solid.triangles, height);
        let (category, rgba) = match o.kind {
            ObjectKind::Box => ("box", [0.33, 0.56, 0.78, 1.0]),
            ObjectKind::Footprint => ("footprint", [0.89, 0.60, 0.30, 1.0]),
        };
        let material = w.material(category, rgba);
        let mesh_name = if known {
            o.name.clone()
        } else {
            format!("{} (nominal height)", o.name)
        };
        let extras = json!({
            "kind": category,
            "height": height,
            "height_known": known,
            "area": o.area,
            "units": units,
        });
        nodes.push(w.node(&o.name, &mesh_name, &mesh, material, &extras));
    }

    // Camera.
    let depth = CAMERA_DEPTH_FRAC
        * if camera_height > 0.0 {
            camera_height
        } else {
            size
        };
    let material = w.material("camera", [0.84, 0.15, 0.16, 1.0]);
    // One photo's camera, or every camera of a room ("camera" is the first photo's).
    let cameras = if map.cameras.is_empty() {
        std::slice::from_ref(&map.camera)
    } else {
        map.cameras.as_slice()
    };
    for (k, camera) in cameras.iter().enumerate() {
        let height = if k == 0 {
            camera_height
        } else {
            check(|| format!("cameras[{k}].height"), camera.height)?
        };
        let mesh = camera_pyramid(camera, height, depth);
        let mut extras = json!({
            "pitch_deg": camera.pitch_deg,
            "roll_deg": camera.roll_deg,
            "height": height,
            "horizontal_fov_deg": camera.horizontal_fov_deg,
            "units": units,
        });
        if let Some(h) = camera.heading_deg {
            extras["heading_deg"] = json!(h);
            extras["photo"] = json!(k + 1);
        }
        let name = if k == 0 {
            "camera".to_owned()
        } else {
            format!("camera {}", k + 1)
        };
        nodes.push(w.node(&name, &name, &mesh, material, &extras));
    }

    let extras = json!({
        "units": units,
        "frame": "glTF (X, Y, Z) = map (x, z, -y): x right, y forward, z up",
        "warnings": map.warnings,
    });
    w.finish(nodes, &extras)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Signed volume of a closed mesh by the divergence theorem.
    fn volume(m: &MeshData) -> f64 {
        m.indices
            .chunks_exact(3)
            .map(|t| {
                let p = |i: u32| m.positions[i as usize].map(f64::from);
                dot(p(t[0]), cross(p(t[1]), p(t[2]))) / 6.0
            })
            .sum()
    }

    #[test]
    fn frame_conversion_is_a_rotation() {
        // x right, y forward, z up -> X right, Y up, Z backward.
        let bits = |v: [f32; 3]| v.map(f32::to_bits);
        assert_eq!(bits(gltf_from_map([1.0, 0.0, 0.0])), bits([1.0, 0.0, 0.0]));
        assert_eq!(bits(gltf_from_map([0.0, 1.0, 0.0])), bits([0.0, 0.0, -1.0]));
        assert_eq!(bits(gltf_from_map([0.0, 0.0, 1.0])), bits([0.0, 1.0, 0.0]));
    }

    #[test]
    fn prism_of_a_non_convex_ring_is_closed_with_outward_normals() {
        let ring = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let solid = solid_ring(&ring, "L").unwrap().unwrap();
        let m = prism(&solid.ring, &solid.triangles, 0.5);
        assert_relative_eq!(volume(&m), 3.0 * 0.5, max_relative = 1e-12);
        // Each stored normal agrees with its triangle's winding.
        for t in m.indices.chunks_exact(3) {
            let p = |i: u32| m.positions[i as usize].map(f64::from);
            let n = cross(sub(p(t[1]), p(t[0])), sub(p(t[2]), p(t[0])));
            assert!(dot(n, m.normals[t[0] as usize].map(f64::from)) > 0.0);
        }
    }

    #[test]
    fn clockwise_footprint_gives_positive_volume() {
        let ring = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        let solid = solid_ring(&ring, "cw").unwrap().unwrap();
        assert_relative_eq!(volume(&prism(&solid.ring, &solid.triangles, 2.0)), 2.0);
    }

    #[test]
    fn camera_pyramid_is_closed_and_looks_forward_and_down() {
        let (scene, _) =
            vpmap_metrology::synth::synthesize(&vpmap_metrology::synth::SynthOptions::default())
                .unwrap();
        let map =
            vpmap_metrology::map::build_map(&scene, &vpmap_metrology::map::BuildOptions::default())
                .unwrap();
        let m = camera_pyramid(&map.camera, 1.5, 0.45);
        assert!(volume(&m) > 0.0);
        // glTF -Z is forward, +Y up: the base is ahead of and below the apex.
        let mean_z: f32 = m.positions.iter().map(|p| p[2]).sum::<f32>() / m.positions.len() as f32;
        let mean_y: f32 = m.positions.iter().map(|p| p[1]).sum::<f32>() / m.positions.len() as f32;
        assert!(mean_z < 0.0 && mean_y < 1.5);
    }

    #[test]
    fn camera_axes_match_the_synthetic_pinhole_camera() {
        use vpmap_metrology::scene::ImageSize;
        use vpmap_metrology::synth::PinholeCamera;
        let image = ImageSize {
            width: 1600,
            height: 1200,
        };
        for pitch_deg in [0.0, 12.0, 35.0] {
            for roll_deg in [-25.0, -4.0, 0.0, 3.0, 30.0] {
                let truth = PinholeCamera {
                    image,
                    focal_px: 1200.0,
                    principal_point_px: image.centre(),
                    height_m: 1.5,
                    pitch_rad: f64::to_radians(pitch_deg),
                    roll_rad: f64::to_radians(roll_deg),
                };
                let (r, d, f) = truth.axes();
                let (right, up, forward) = camera_axes(pitch_deg, roll_deg);
                for (ours, theirs) in [
                    (right, [r.x, r.y, r.z]),
                    (up, [-d.x, -d.y, -d.z]),
                    (forward, [f.x, f.y, f.z]),
                ] {
                    for k in 0..3 {
                        assert_relative_eq!(ours[k], theirs[k], epsilon = 1e-12);
                    }
                }
                // Positive roll: the camera's right side is tilted up.
                assert_eq!(right[2] > 1e-12, roll_deg > 0.0, "roll {roll_deg}");
            }
        }
    }

    #[test]
    fn camera_pyramid_shows_the_roll() {
        let (scene, _) =
            vpmap_metrology::synth::synthesize(&vpmap_metrology::synth::SynthOptions::default())
                .unwrap();
        let mut map =
            vpmap_metrology::map::build_map(&scene, &vpmap_metrology::map::BuildOptions::default())
                .unwrap();
        let (sp, cp) = map.camera.pitch_deg.to_radians().sin_cos();
        let forward = [0.0, cp, -sp];
        let mut lifts = Vec::new();
        for roll_deg in [-20.0, 0.0, 20.0] {
            map.camera.roll_deg = roll_deg;
            let (apex, base) = camera_frustum(&map.camera, 1.5, 0.45);
            // The bottom edge of the image (corner 0 to 1) runs along the rolled right axis:
            // perpendicular to the viewing direction, at the roll angle from the image's
            // unrolled horizontal (map x) within the image plane.
            let e = sub(base[1], base[0]);
            assert_relative_eq!(dot(e, forward), 0.0, epsilon = 1e-12);
            let up0 = [0.0, sp, cp];
            let angle = dot(e, up0).atan2(e[0]).to_degrees();
            assert_relative_eq!(angle, roll_deg, epsilon = 1e-9);
            // The image's right side (corners 1, 2) is raised by a positive roll.
            let side_lift = base[1][2] + base[2][2] - base[0][2] - base[3][2];
            assert_eq!(side_lift > 1e-9, roll_deg > 0.0, "roll {roll_deg}");
            assert_eq!(side_lift < -1e-9, roll_deg < 0.0, "roll {roll_deg}");
            // The roll turns the pyramid about its viewing axis: the base stays `depth` ahead.
            for c in base {
                assert_relative_eq!(dot(sub(c, apex), forward), 0.45, epsilon = 1e-12);
            }
            // The mesh (glTF +Y up, +X right): the right half is higher for a positive roll.
            let m = camera_pyramid(&map.camera, 1.5, 0.45);
            assert!(volume(&m) > 0.0);
            let mean_y = |right: bool| {
                let ys: Vec<f32> = m
                    .positions
                    .iter()
                    .filter(|p| if right { p[0] > 1e-6 } else { p[0] < -1e-6 })
                    .map(|p| p[1])
                    .collect();
                ys.iter().sum::<f32>() / ys.len() as f32
            };
            lifts.push(mean_y(true) - mean_y(false));
        }
        // (The field of view need not be centred, so compare with no roll.)
        assert!(lifts[0] < lifts[1] - 0.05, "{lifts:?}");
        assert!(lifts[2] > lifts[1] + 0.05, "{lifts:?}");
    }

    #[test]
    fn huge_coordinates_are_out_of_range_not_infinite_floats() {
        assert!(matches!(
            check(|| "x".to_owned(), 1e300),
            Err(RenderError::OutOfRange { .. })
        ));
        assert!(matches!(
            check(|| "x".to_owned(), f64::NAN),
            Err(RenderError::NonFinite { .. })
        ));
    }
}
