// The room's cameras in the 3D view (map.json `cameras`, one per photo): each as a wire-frame
// viewing pyramid from its centre through its image's corners, with its photo's number above
// it, the active photo's camera in orange. The pyramid's geometry (frustumSegments) is pure,
// for the unit tests; cameraGroup builds the three.js objects.
//
// glTF is +Y up; a map point (x, y, z) is (x, z, -y) (docs/map-format.md).

const finite = (v) => typeof v === 'number' && Number.isFinite(v);

/** A map point in the 3D view's (glTF) frame. */
export const toGltf = (p) => [p[0], p[2], -p[1]];

/**
 * The edges of a camera's viewing pyramid, `depth` map units deep along its optical axis, as
 * pairs of glTF points `[[a, b], ...]`: four from the camera's centre to its image corners, then
 * the image rectangle's four sides. Null when the camera lacks `position` (3 numbers),
 * `rotation_map_from_camera` or its intrinsics (`k_matrix`, else `focal_px` and
 * `principal_point`) and `image`.
 */
export function frustumSegments(cam, depth) {
  const pos = cam?.position;
  const r = cam?.rotation_map_from_camera;
  const img = cam?.image;
  if (!Array.isArray(pos) || pos.length < 3 || !pos.every(finite)) return null;
  if (!Array.isArray(r) || r.length !== 3 || !r.every((row) => Array.isArray(row) && row.length === 3 && row.every(finite))) return null;
  if (!img || !(img.width > 0) || !(img.height > 0)) return null;
  const k = cam.k_matrix;
  const f = Array.isArray(k) ? k[0]?.[0] : cam.focal_px;
  const cx = Array.isArray(k) ? k[0]?.[2] : cam.principal_point?.[0];
  const cy = Array.isArray(k) ? k[1]?.[2] : cam.principal_point?.[1];
  if (!(f > 0) || !finite(cx) || !finite(cy)) return null;
  const corner = ([u, v]) => {
    // K^-1 (u, v, 1): depth 1 along the optical axis; then map-from-camera.
    const d = [(u - cx) / f, (v - cy) / f, 1];
    const m = r.map((row) => row[0] * d[0] + row[1] * d[1] + row[2] * d[2]);
    return toGltf([pos[0] + depth * m[0], pos[1] + depth * m[1], pos[2] + depth * m[2]]);
  };
  const apex = toGltf(pos);
  const c = [[0, 0], [img.width, 0], [img.width, img.height], [0, img.height]].map(corner);
  return [...c.map((p) => [apex, p]), ...c.map((p, i) => [p, c[(i + 1) % 4]])];
}

/** A square canvas with the photo's number, for the label above a camera. */
function numberCanvas(text, colour) {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 64;
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = colour;
  ctx.beginPath();
  ctx.arc(32, 32, 28, 0, Math.PI * 2);
  ctx.fill();
  ctx.fillStyle = '#fff';
  ctx.font = 'bold 36px sans-serif';
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.fillText(text, 32, 34);
  return canvas;
}

/** The three.js group of every camera: `depth` the pyramids' depth (map units). */
export function cameraGroup(THREE, cameras, active, depth) {
  const g = new THREE.Group();
  g.name = 'room-cameras';
  cameras.forEach((cam, i) => {
    const segs = frustumSegments(cam, depth);
    if (!segs) return;
    const on = i === active;
    const colour = on ? '#e65100' : '#37474f';
    const geom = new THREE.BufferGeometry();
    geom.setAttribute('position', new THREE.Float32BufferAttribute(segs.flat(2), 3));
    const lines = new THREE.LineSegments(geom, new THREE.LineBasicMaterial({ color: colour }));
    lines.name = `camera-${i + 1}`;
    g.add(lines);
    const label = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(numberCanvas(String(i + 1), colour)), depthTest: false }));
    const at = toGltf(cam.position);
    label.position.set(at[0], at[1] + depth * 0.45, at[2]);
    label.scale.set(depth * 0.35, depth * 0.35, 1);
    g.add(label);
  });
  return g;
}
