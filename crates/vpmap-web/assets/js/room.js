// The room: several photos of one room, each with its own scene (docs/scene-format.md, "A room
// of several photos"). Pure functions on the list of scenes, no DOM, so the unit tests
// (e2e/unit/room.test.mjs) run them in Node.
//
// The room file is `{"version": 1, "photos": [SCENE, ...]}`; a room of one photo is saved (and
// sent to /api/build) as that photo's scene file, exactly as a page of one photo always did. An
// object with the same `name` in several photos is one object: linking is naming. Photos are
// numbered from 1 in what the page says ("photo 2") and from 0 in field paths (`photos[1]`), as
// the server's messages do.

import { buildBlocker, messagePoint, normaliseScene } from './scene.js';

/** The body to save or to send to /api/build: the scene itself for one photo, else a room file. */
export function roomBody(scenes) {
  if (scenes.length === 1) return scenes[0];
  return { version: 1, photos: scenes };
}

/** A parsed JSON value is a room file (rather than a single-photo scene). */
export function isRoomFile(value) {
  return !!value && typeof value === 'object' && !Array.isArray(value) && Array.isArray(value.photos);
}

/**
 * The scenes of a parsed scene file or room file: `{scenes}` (each normalised, scene.js
 * normaliseScene) or `{error}` naming the photo at fault. `room` says which it was.
 */
export function parseRoom(value) {
  if (!isRoomFile(value)) {
    const error = normaliseScene(value);
    return error ? { error } : { scenes: [value], room: false };
  }
  if (value.version !== 1) return { error: `unsupported room file version ${JSON.stringify(value.version)} (expected 1)` };
  if (value.photos.length === 0) return { error: 'the room file has no photos (`photos` is empty)' };
  for (const [i, scene] of value.photos.entries()) {
    const error = normaliseScene(scene);
    if (error) return { error: `photo ${i + 1} (\`photos[${i}]\`): ${error}` };
  }
  return { scenes: value.photos, room: true };
}

/**
 * Why the room cannot be built yet: `{photo, message}` (photo a 0-based index; the message
 * names it when the room has several photos), or null.
 */
export function roomBlocker(scenes) {
  if (!scenes.length) return { photo: null, message: buildBlocker(null) };
  for (const [i, scene] of scenes.entries()) {
    const why = buildBlocker(scene);
    if (why) return { photo: i, message: scenes.length > 1 ? `photo ${i + 1}: ${why}` : why };
  }
  return null;
}

/**
 * The photo a server message is about (0-based), or null: the first field path into the room
 * (`photos[2].objects[1]...`, 0-based) or else the first "photo N" it names (1-based). A
 * message about a single-photo scene names no photo; with `count` 1 it is about photo 0.
 */
export function messagePhoto(message, count) {
  const text = String(message || '');
  const path = /\bphotos\[(\d+)\]/.exec(text);
  let i = null;
  if (path) i = Number(path[1]);
  else {
    const named = /\bphoto (\d+)\b/i.exec(text);
    if (named) i = Number(named[1]) - 1;
    else if (count === 1) i = 0;
  }
  return i !== null && i >= 0 && i < count ? i : null;
}

/**
 * What a server message (a build error) is about in the room: `{photo, message}` plus, when it
 * names a point or an object of that photo, `path`, `p` or `object` and `note` as scene.js
 * messagePoint gives them for that photo's scene. Null when it names no photo.
 */
export function roomProblem(message, scenes) {
  const photo = messagePhoto(message, scenes.length);
  if (photo === null) return null;
  // `photos[2].objects[1].base.near` -> `objects[1].base.near`, in that photo's scene.
  const own = String(message).replace(new RegExp(`\`?photos\\[${photo}\\]\\.((?:floor|objects)\\[\\d+\\][\\w.\\[\\]]*)\`?`, 'g'), '`$1`');
  const point = messagePoint(own, scenes[photo]);
  return { photo, message: String(message), ...(point || {}) };
}

/**
 * The names of objects in the other photos of the room, for linking an object of photo
 * `active` to them: `[{name, photos}]` (photos: 0-based indices where the name is used), in
 * order of first use, leaving out names photo `active` already uses.
 */
export function linkCandidates(scenes, active) {
  const own = new Set((scenes[active]?.objects || []).map((o) => o.name));
  const out = new Map();
  scenes.forEach((scene, i) => {
    if (i === active) return;
    for (const o of scene?.objects || []) {
      if (!o.name || own.has(o.name)) continue;
      if (!out.has(o.name)) out.set(o.name, { name: o.name, photos: [] });
      const entry = out.get(o.name);
      if (!entry.photos.includes(i)) entry.photos.push(i);
    }
  });
  return [...out.values()];
}

/** For each object name of photo `active`: the other photos (0-based) that name it too (a shared, linked object). */
export function sharedWith(scenes, active) {
  const out = new Map();
  for (const o of scenes[active]?.objects || []) {
    const others = [];
    scenes.forEach((scene, i) => {
      if (i !== active && (scene?.objects || []).some((x) => x.name === o.name)) others.push(i);
    });
    out.set(o.name, others);
  }
  return out;
}

/** "photo 2", "photos 1 and 3", "photos 1, 2 and 4" for 0-based indices. */
export function photoList(indices) {
  const n = indices.map((i) => String(i + 1));
  if (n.length === 0) return '';
  if (n.length === 1) return `photo ${n[0]}`;
  return `photos ${n.slice(0, -1).join(', ')} and ${n[n.length - 1]}`;
}

/** The file name to save the room under: the first photo's name with `.room.json`. */
export function roomFileName(firstPhotoName) {
  const base = (firstPhotoName || 'room').replace(/\.[^.]+$/, '');
  return `${base}.room.json`;
}

/**
 * The camera of photo `index` in a build answer, in the shape of the answer's `camera` (what the
 * camera bar and the horizon on the photo use): `{pitch_deg, roll_deg, focal_px,
 * principal_point, height, horizon, lens_distortion, uncertainty}`. Photo 0, or an answer without `map.cameras`
 * (a single photo): the answer's own camera. Null when the answer has no camera for it.
 */
export function cameraOf(build, index) {
  if (!build) return null;
  const cams = build.map?.cameras;
  const first = () => (build.camera ? { ...build.camera, uncertainty: build.map?.camera?.uncertainty ?? null } : null);
  if (!Array.isArray(cams) || cams.length === 0) return index === 0 ? first() : null;
  const c = cams[index];
  if (!c) return null;
  if (index === 0 && build.camera) return first();
  const vps = Array.isArray(c.vanishing_points) ? c.vanishing_points : [];
  return {
    pitch_deg: c.pitch_deg,
    roll_deg: c.roll_deg,
    focal_px: c.focal_px,
    principal_point: c.principal_point,
    height: c.height,
    horizon: vps.length >= 2 ? [vps[0], vps[1]] : null,
    lens_distortion: c.lens_distortion ?? null,
    uncertainty: c.uncertainty ?? null,
  };
}
