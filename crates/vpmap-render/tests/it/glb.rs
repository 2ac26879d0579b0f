//! The GLB model, parsed back with the `gltf` crate (which also validates it).

use approx::assert_relative_eq;
use gltf::Gltf;
use gltf::mesh::util::ReadIndices;
use vpmap_metrology::map::FloorMap;
use vpmap_render::model_glb;

use crate::{awkward_map, default_map, map_with, save_for_review};

/// One mesh read back: positions, normals and triangle indices.
struct ReadMesh {
    name: String,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    indices: Vec<u32>,
    accessor_min: Vec<f32>,
    accessor_max: Vec<f32>,
}

fn json_f32s(v: &serde_json::Value) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

/// Parse a GLB, checking its chunk layout by hand, and read every node's mesh.
fn read(bytes: &[u8]) -> (Gltf, Vec<(String, ReadMesh)>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(word(4), 2, "GLB version");
    assert_eq!(word(8), bytes.len(), "GLB total length");
    let json_len = word(12);
    assert_eq!(&bytes[16..20], b"JSON");
    assert_eq!(json_len % 4, 0, "JSON chunk padded to 4 bytes");
    let bin_at = 20 + json_len;
    let bin_len = word(bin_at);
    assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
    assert_eq!(bin_len % 4, 0, "BIN chunk padded to 4 bytes");
    assert_eq!(bin_at + 8 + bin_len, bytes.len());

    let gltf = Gltf::from_slice(bytes).expect("a valid glTF");
    let blob = gltf.blob.clone().expect("a binary chunk");
    assert_eq!(gltf.buffers().count(), 1);
    let buffer = gltf.buffers().next().unwrap();
    assert!(buffer.length() <= blob.len());
    let mut meshes = Vec::new();
    for node in gltf.nodes() {
        let mesh = node.mesh().expect("every node has a mesh");
        assert_eq!(mesh.primitives().count(), 1);
        let prim = mesh.primitives().next().unwrap();
        assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles);
        let reader = prim.reader(|_| Some(&blob));
        let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
        let ReadIndices::U32(indices) = reader.read_indices().unwrap() else {
            panic!("indices are not u32");
        };
        let accessor = prim.get(&gltf::Semantic::Positions).unwrap();
        meshes.push((
            node.name().unwrap().to_owned(),
            ReadMesh {
                name: mesh.name().unwrap().to_owned(),
                positions,
                normals,
                indices: indices.collect(),
                accessor_min: json_f32s(&accessor.min().unwrap()),
                accessor_max: json_f32s(&accessor.max().unwrap()),
            },
        ));
    }
    (gltf, meshes)
}

fn bbox(points: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

fn vec(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Signed volume enclosed by a triangle mesh (divergence theorem): positive for a closed
/// surface wound counter-clockwise seen from outside.
fn signed_volume(m: &ReadMesh) -> f64 {
    m.indices
        .chunks_exact(3)
        .map(|t| {
            let p = |i: u32| vec(m.positions[i as usize]);
            dot(p(t[0]), cross(p(t[1]), p(t[2]))) / 6.0
        })
        .sum()
}

/// Shoelace area of a footprint rounded to `f32`, as the model stores it.
fn f32_area(footprint: &[[f64; 2]]) -> f64 {
    let pts: Vec<[f64; 2]> = footprint
        .iter()
        .map(|p| [f64::from(p[0] as f32), f64::from(p[1] as f32)])
        .collect();
    let n = pts.len();
    (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

/// Everything the brief asks of a model, for any map.
fn check_model(map: &FloorMap) {
    let bytes = model_glb(map).unwrap();
    let (gltf, meshes) = read(&bytes);
    assert_eq!(gltf.meshes().count(), map.objects.len() + 2);
    assert_eq!(gltf.scenes().count(), 1);
    let names: Vec<&str> = meshes.iter().map(|(n, _)| n.as_str()).collect();
    assert!(names[0].starts_with("floor"));
    assert_eq!(names[names.len() - 1], "camera");
    let object_names: Vec<&str> = map.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(&names[1..names.len() - 1], object_names.as_slice());

    for (name, m) in &meshes {
        let (lo, hi) = bbox(&m.positions);
        assert_eq!(m.accessor_min, lo.to_vec(), "{name}: POSITION min");
        assert_eq!(m.accessor_max, hi.to_vec(), "{name}: POSITION max");
        assert_eq!(m.normals.len(), m.positions.len());
        assert_eq!(m.indices.len() % 3, 0);
        assert!(
            m.indices.iter().all(|&i| (i as usize) < m.positions.len()),
            "{name}: index out of range"
        );
        // Flat normals: unit length and on the side the winding faces.
        for t in m.indices.chunks_exact(3) {
            let p = |i: u32| vec(m.positions[i as usize]);
            let face = cross(sub(p(t[1]), p(t[0])), sub(p(t[2]), p(t[0])));
            for &i in t {
                let n = vec(m.normals[i as usize]);
                assert_relative_eq!(dot(n, n).sqrt(), 1.0, epsilon = 1e-6);
                assert!(dot(n, face) > 0.0, "{name}: normal against winding");
            }
        }
    }

    for (o, (_, m)) in map.objects.iter().zip(&meshes[1..]) {
        let (lo, hi) = bbox(&m.positions);
        let height = o.height.unwrap_or_else(|| f64::from(hi[1]));
        if o.height.is_none() {
            assert!(m.name.contains("nominal height"), "{}", m.name);
        }
        // Vertical extent: glTF Y from the floor to the height.
        assert_eq!(lo[1].to_bits(), 0.0f32.to_bits(), "{}", o.name);
        assert_relative_eq!(f64::from(hi[1]), height, max_relative = 1e-6);
        // Footprint box: glTF X = map x, glTF Z = -map y.
        let xs = o.footprint.iter().map(|p| p[0]);
        let ys = o.footprint.iter().map(|p| p[1]);
        let min_x = xs.clone().fold(f64::INFINITY, f64::min);
        let max_x = xs.fold(f64::NEG_INFINITY, f64::max);
        let min_y = ys.clone().fold(f64::INFINITY, f64::min);
        let max_y = ys.fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(lo[0], min_x as f32);
        assert_eq!(hi[0], max_x as f32);
        assert_eq!(lo[2], -(max_y as f32));
        assert_eq!(hi[2], -(min_y as f32));
        // A closed, consistently wound solid encloses exactly footprint area x height.
        let expected = f32_area(&o.footprint) * f64::from(hi[1]);
        assert_relative_eq!(signed_volume(m), expected, max_relative = 1e-9);
        assert_relative_eq!(f32_area(&o.footprint), o.area, max_relative = 1e-5);
    }

    // The camera is a closed solid around (0, height, 0).
    let (_, camera) = &meshes[meshes.len() - 1];
    assert!(signed_volume(camera) > 0.0);
    let (lo, hi) = bbox(&camera.positions);
    let h = map.camera.height as f32;
    assert!(lo[1] <= h && h <= hi[1]);
    assert!(hi[2] <= 1e-6, "the camera looks towards -Z (forward)");
}

#[test]
fn default_room_model_matches_the_map() {
    let map = default_map();
    check_model(&map);
    save_for_review("render-check.glb", &model_glb(&map).unwrap());
}

#[test]
fn model_with_unknown_height_and_escaped_name() {
    check_model(&awkward_map());
}

#[test]
fn models_of_random_rooms_in_metres_and_camera_heights() {
    for seed in 1..6 {
        let options = vpmap_metrology::synth::SynthOptions {
            seed,
            with_scale: seed % 2 == 0,
            boxes: 2 + seed as usize,
            prisms: 2,
            ..vpmap_metrology::synth::SynthOptions::default()
        };
        check_model(&map_with(&options));
    }
}

#[test]
fn floor_mesh_covers_the_floor_polygon_facing_up() {
    let map = default_map();
    let (_, meshes) = read(&model_glb(&map).unwrap());
    let (name, floor) = &meshes[0];
    assert_eq!(name, "floor");
    assert!(floor.positions.iter().all(|p| p[1].to_bits() == 0));
    let area: f64 = floor
        .indices
        .chunks_exact(3)
        .map(|t| {
            let p = |i: u32| vec(floor.positions[i as usize]);
            // Upward normal (+Y) for every triangle.
            let n = cross(sub(p(t[1]), p(t[0])), sub(p(t[2]), p(t[0])));
            assert!(n[1] > 0.0);
            n[1] / 2.0
        })
        .sum();
    assert_relative_eq!(area, f32_area(&map.floor), max_relative = 1e-9);
}

#[test]
fn map_without_floor_gets_a_rectangle_around_objects_and_camera() {
    let mut map = default_map();
    map.floor.clear();
    map.free_space.clear();
    let (_, meshes) = read(&model_glb(&map).unwrap());
    let (name, floor) = &meshes[0];
    assert_eq!(name, "floor (bounding rectangle)");
    let (lo, hi) = bbox(&floor.positions);
    for o in &map.objects {
        for p in &o.footprint {
            assert!(lo[0] < p[0] as f32 && (p[0] as f32) < hi[0]);
            assert!(lo[2] < -p[1] as f32 && (-p[1] as f32) < hi[2]);
        }
    }
    assert!(lo[0] < 0.0 && hi[2] > 0.0, "contains the station point");
}
