// The vpmap server's JSON API. Every call takes an AbortSignal; errors carry the server's
// `{"error": "..."}` message.

export class ApiError extends Error {
  constructor(message, status) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
  }
}

/** True for the rejection of an aborted request (which callers ignore). */
export function isAbort(err) {
  return err && (err.name === 'AbortError' || err.code === 20);
}

async function call(path, { method = 'GET', body, type, signal } = {}) {
  const headers = {};
  if (type) headers['Content-Type'] = type;
  let res;
  try {
    res = await fetch(path, { method, body, headers, signal, cache: 'no-store' });
  } catch (err) {
    if (isAbort(err)) throw err;
    throw new ApiError(`cannot reach the vpmap server (${err.message}); is \`vpmap serve\` still running?`, 0);
  }
  const text = await res.text();
  let json = null;
  try {
    json = text ? JSON.parse(text) : null;
  } catch {
    // Not JSON: fall through with the text.
  }
  if (!res.ok) {
    const msg = (json && typeof json.error === 'string' && json.error) || text.trim() || res.statusText;
    throw new ApiError(msg || `HTTP ${res.status}`, res.status);
  }
  if (json === null) throw new ApiError(`the server answered ${path} with something that is not JSON`, res.status);
  return json;
}

function query(params) {
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(params)) {
    if (v === undefined || v === null || v === '') continue;
    q.set(k, String(v));
  }
  const s = q.toString();
  return s ? `?${s}` : '';
}

/** `GET /api/example` -> `{scene, photo_png_base64}`. */
export function getExample(signal) {
  return call('api/example', { signal });
}

/**
 * `POST /api/build` with the scene -> `{map, svg, glb_base64, occupancy, camera, warnings}`.
 * A null `method` or `click_sigma` is left out: the server's default method, the fit's own
 * estimate of the click noise; `hidden_free` is sent only when set.
 */
export function build(scene, { method, resolution, robot_radius, click_sigma, hidden_free }, signal) {
  return call(`api/build${query({ method, resolution, robot_radius, click_sigma, hidden_free: hidden_free ? 'true' : undefined })}`, {
    method: 'POST',
    body: JSON.stringify(scene),
    type: 'application/json',
    signal,
  });
}

/** `POST /api/detect` with the photo's bytes -> `{scene, segments, vanishing_points, perspective, focal_px, principal_point}`. */
export function detect(photo, { focal_px, principal_point }, signal) {
  return call(
    `api/detect${query({ focal_px, principal_point: principal_point ? principal_point.join(',') : undefined })}`,
    { method: 'POST', body: photo, type: photo.type || 'application/octet-stream', signal },
  );
}

/** `POST /api/plan` -> `{results: [...], grid}`. */
export function plan(request, signal) {
  return call('api/plan', { method: 'POST', body: JSON.stringify(request), type: 'application/json', signal });
}

/**
 * `POST /api/navigate`: a plan request without `planners`, plus `truth`, `planner` and
 * `sensor_range` -> the robot's drive on the true map (docs/web-api.md).
 */
export function navigate(request, signal) {
  return call('api/navigate', { method: 'POST', body: JSON.stringify(request), type: 'application/json', signal });
}

/** `POST /api/photo` with the photo's bytes -> `{id, width, height}`: kept for snapping. */
export function uploadPhoto(photo, signal) {
  return call('api/photo', { method: 'POST', body: photo, type: photo.type || 'application/octet-stream', signal });
}

/** `POST /api/snap` `{photo, click, vanishing_points, click_sigma?, lens_distortion?, principal_point?}` -> `{point, snapped, covariance_px2, edges, note}`. */
export function snapClick(request, signal) {
  return call('api/snap', { method: 'POST', body: JSON.stringify(request), type: 'application/json', signal });
}

/** `POST /api/propose` `{photo, vanishing_points, lens_distortion?, principal_point?}` -> `{proposals: [{corners: {base, top}, score}]}`. */
export function proposeBoxes(request, signal) {
  return call('api/propose', { method: 'POST', body: JSON.stringify(request), type: 'application/json', signal });
}
