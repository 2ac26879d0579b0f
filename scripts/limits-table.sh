#!/usr/bin/env bash
# Re-measures the inputs of docs/limits.md "Measured" on this machine: wall time, peak resident
# memory and the answer of `vpmap` for each, and the memory a grid cell takes (the figure behind
# `vpmap_plan::grid::BYTES_PER_CELL`). Prints a Markdown table.
#
#   bash scripts/limits-table.sh            # builds the release binary first
#   VPMAP=path/to/vpmap bash scripts/limits-table.sh
#
# Needs GNU time (`/usr/bin/time`, Debian package `time`) for peak memory, and python3 for the
# photos and covariances of issue 40's cases and for the server's cases (scripts/limits_server.py,
# which reads the server's memory from /proc: Linux). Writes only to a temporary folder, removed
# at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -z "${VPMAP:-}" ]]; then
  cargo build --release --locked -p vpmap-cli >&2
  VPMAP=$PWD/target/release/vpmap
fi
if [[ ! -x /usr/bin/time ]]; then
  echo "limits-table.sh: /usr/bin/time (GNU time) is needed for peak memory; apt-get install time" >&2
  exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# One row: what, then the command. Runs it, keeps its exit code, wall time, peak memory and the
# first line it printed on stderr (its error) or "ok".
row() {
  local what=$1; shift
  local code=0
  /usr/bin/time -f '%e %M' -o "$tmp/time" "$@" > "$tmp/stdout" 2> "$tmp/stderr" || code=$?
  local secs kib answer
  read -r secs kib < <(tail -n 1 "$tmp/time")
  if [[ $code -eq 0 ]]; then
    answer="ok"
  else
    answer=$(grep -v '^Command exited' "$tmp/stderr" | head -n 1 | cut -c 1-110)
  fi
  printf '| %s | %s s | %s MB | %s | %s |\n' "$what" "$secs" "$((kib / 1024))" "$code" "${answer//|/\\|}"
}

# The bundled example's map.json (the map a photo gives).
"$VPMAP" build examples/office.json --out "$tmp/office" > /dev/null
map=$tmp/office/map.json

# A 300 x 300 comb: walls every third row, each open at alternate ends (the MBPP worst case).
write_comb() {
  local w=300 h=300
  printf 'type octile\nheight %d\nwidth %d\nmap\n' "$h" "$w"
  for ((y = 0; y < h; y++)); do
    if (( y >= 2 && y < h - 2 && (y - 2) % 3 == 0 )); then
      local k=$(((y - 2) / 3)) line
      if (( k % 2 == 0 )); then line="$(printf '@%.0s' $(seq 1 $((w - 2)))).@"; else line="@.$(printf '@%.0s' $(seq 1 $((w - 2))))"; fi
      printf '%s\n' "$line"
    else
      printf '%s\n' "$(printf '.%.0s' $(seq 1 $w))"
    fi
  done
}
write_comb > "$tmp/comb.map"

# A PGM whose header says 14000 x 14000 (the pixels are missing) and its ROS YAML.
printf 'P5\n14000 14000\n255\n' > "$tmp/huge.pgm"
printf 'image: huge.pgm\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n' > "$tmp/huge.yaml"
printf 'image: /dev/zero\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n' > "$tmp/zero.yaml"
mkfifo "$tmp/fifo.map"
ln -s /dev/zero "$tmp/zero.map"

echo "| input | wall time | peak memory | exit | answer |"
echo "|---|---|---|---|---|"
row "comb 300x300, \`--planner mbpp-closer\`" "$VPMAP" plan "$tmp/comb.map" --from 150,0 --to 150,299 --planner mbpp-closer
row "comb 300x300, \`--planner mbpp\`" "$VPMAP" plan "$tmp/comb.map" --from 150,0 --to 150,299 --planner mbpp
row "PGM header 14000 x 14000" "$VPMAP" plan "$tmp/huge.yaml" --from 1,1 --to 2,2
row "YAML \`image: /dev/zero\`" "$VPMAP" plan "$tmp/zero.yaml" --from 1,1 --to 2,2
row "\`zero.map\`, a link to \`/dev/zero\`" "$VPMAP" plan "$tmp/zero.map" --from 1,1 --to 2,2
row "\`fifo.map\`, a FIFO" "$VPMAP" plan "$tmp/fifo.map" --from 1,1 --to 2,2
row "office map.json \`--resolution 0.0007\`" "$VPMAP" plan "$map" --resolution 0.0007 --from=1.1,1.7 --to=0.2,5
echo

# Issue 40: outputs, snapping and click covariances.
# PNGs written by a few lines of Python (zlib, streamed): a grey 8000 x 8000 photo, and a 16-bit
# RGBA 12000 x 12000 one with an EXIF quarter turn (orientation 6), about 1.1 MB each.
write_png() {
  python3 - "$@" <<'PY'
import struct, sys, zlib
path, side, depth, orientation = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
colour = 0 if depth == 8 else 6
row = b"\0" + bytes(side * (1 if depth == 8 else 8))
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
z = zlib.compressobj(9)
idat = b"".join(z.compress(row) for _ in range(side)) + z.flush()
out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", side, side, depth, colour, 0, 0, 0))
if orientation:
    out += chunk(b"eXIf", b"MM\0*\0\0\0\x08\0\x01\x01\x12\0\x03\0\0\0\x01" + struct.pack(">H", orientation) + bytes(6))
open(path, "wb").write(out + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
PY
}
"$VPMAP" synth --seed 3 -o "$tmp/synth.json" > /dev/null
sed 's/"width": [0-9]*/"width": 12000/; s/"height": [0-9]*/"height": 12000/' "$tmp/synth.json" > "$tmp/synth12000.json"
write_png "$tmp/grey8000.png" 8000 8 0
write_png "$tmp/turned12000.png" 12000 16 6
printf '{"version": 1, "photos": [%s, %s]}' "$(cat "$tmp/synth.json")" "$(cat "$tmp/synth.json")" > "$tmp/room.json"
covariances() {
  python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); s["click_covariances_px2"]={"objects[0].base.near": [[float(sys.argv[2]), 0], [0, float(sys.argv[2])]]}; print(json.dumps(s))' "$tmp/synth.json" "$1"
}
covariances 1e-150 > "$tmp/cov-tiny.json"
covariances 1e300 > "$tmp/cov-huge.json"
mkfifo "$tmp/out.fifo"
printf '| input | wall time | peak memory | exit | answer |\n|---|---|---|---|---|\n'
row "\`snap\` on an 8000 x 8000 photo of another size (was 1.9 s, 434 MB)" "$VPMAP" snap "$tmp/grey8000.png" "$tmp/synth.json" -o "$tmp/snapped.json"
row "\`snap\` on a 16-bit 12000 x 12000 PNG with an EXIF quarter turn (was 2.2 GB)" "$VPMAP" snap "$tmp/turned12000.png" "$tmp/synth12000.json" -o "$tmp/snapped.json"
sed 's/"width": [0-9]*/"width": 8000/; s/"height": [0-9]*/"height": 8000/' "$tmp/synth.json" > "$tmp/synth8000.json"
row "\`snap\` on a grey 8000 x 8000 photo of its size (within the limits: decoded, nothing snaps)" "$VPMAP" snap "$tmp/grey8000.png" "$tmp/synth8000.json" -o "$tmp/snapped.json"
row "\`snap\` on a room of 2 photos given 1 photo" "$VPMAP" snap "$tmp/grey8000.png" "$tmp/room.json" -o "$tmp/snapped.json"
row "\`synth -o\` a FIFO (became a regular file)" "$VPMAP" synth -o "$tmp/out.fifo"
row "\`synth --truth /dev/null\` (as root: the device replaced)" "$VPMAP" synth -o "$tmp/s.json" --truth /dev/null
row "\`synth --truth X -o X\` (the truth lost)" "$VPMAP" synth -o "$tmp/s.json" --truth "$tmp/s.json"
row "\`synth --noise 1e308\` (exit 0, nulls written)" "$VPMAP" synth --noise 1e308 -o "$tmp/s.json"
row "\`build\`, a click variance of 1e-150 px^2 (was \"RMS 7.6e61 px\")" "$VPMAP" build "$tmp/cov-tiny.json" --out "$tmp/cov-out"
row "\`build\`, a click variance of 1e300 px^2 (300-digit numbers)" "$VPMAP" build "$tmp/cov-huge.json" --out "$tmp/cov-out"
# Rooms at the limit of 1,000 objects in all photos (issue 40: 4 photos of 500 objects took 20 s,
# 16 of 100 took 50 s before the limit): a synthetic room of 4 photos and 99 boxes, its second
# photo repeated up to 10 photos (979 objects) and beyond the limit (1078); its photos cut to 62
# objects and repeated to 16 photos (992).
"$VPMAP" synth --photos 4 --boxes 99 --seed 3 -o "$tmp/room4.json" > /dev/null
python3 - "$tmp" <<'PY'
import copy, json, sys
tmp = sys.argv[1]
room = json.load(open(f"{tmp}/room4.json"))
count = lambda r: sum(len(p["objects"]) for p in r["photos"])
ten = copy.deepcopy(room)
while count(ten) + len(room["photos"][1]["objects"]) <= 1000:
    ten["photos"].append(copy.deepcopy(room["photos"][1]))
json.dump(ten, open(f"{tmp}/room-most.json", "w"))
ten["photos"].append(copy.deepcopy(room["photos"][1]))
json.dump(ten, open(f"{tmp}/room-over.json", "w"))
sixteen = copy.deepcopy(room)
for p in sixteen["photos"]:
    p["objects"] = p["objects"][:62]
while len(sixteen["photos"]) < 16:
    sixteen["photos"].append(copy.deepcopy(sixteen["photos"][len(sixteen["photos"]) % 4]))
json.dump(sixteen, open(f"{tmp}/room-16.json", "w"))
# The same with a principal point prior on every photo, as `vpmap detect` writes it (its test,
# map/priors.rs: the joint fit once more a photo, from its answer).
priors = copy.deepcopy(sixteen)
for p in priors["photos"]:
    w, h = p["image"]["width"], p["image"]["height"]
    p["principal_point_sd_px"] = round(0.015 * (w * w + h * h) ** 0.5, 3)
json.dump(priors, open(f"{tmp}/room-16-priors.json", "w"))
# The same with a lens whose k has an sd on every photo (its spread: the joint fit twice more a
# photo; the clicks' profile of k adds no refit when they do not reject it).
for p in sixteen["photos"]:
    p["lens_distortion"] = {"k": 0.0, "k_sd": 0.01}
json.dump(sixteen, open(f"{tmp}/room-16-lens.json", "w"))
# One photo of 500 objects (the limit): the room's first photo, its objects repeated under new
# names, with a lens whose k has an sd (three fits).
photo = copy.deepcopy(room["photos"][0])
objects, k = [], 0
while len(objects) < 500:
    for o in photo["objects"]:
        objects.append(dict(o, name=f"{o['name']}-{k}"))
    k += 1
photo["objects"] = objects[:500]
photo["lens_distortion"] = {"k": 0.0, "k_sd": 0.01}
json.dump(photo, open(f"{tmp}/photo-500.json", "w"))
PY
row "\`build\`, one photo of 500 objects (the limit) and a lens with an sd" "$VPMAP" build "$tmp/photo-500.json" --out "$tmp/photo-out"
row "\`build\`, a room of 4 photos and 99 boxes (385 objects in all)" "$VPMAP" build "$tmp/room4.json" --out "$tmp/room-out"
row "\`build\`, a room of 10 photos, 979 objects in all (within the limit)" "$VPMAP" build "$tmp/room-most.json" --out "$tmp/room-out"
row "\`build\`, a room of 16 photos, 992 objects in all (16 x 100 took 50 s)" "$VPMAP" build "$tmp/room-16.json" --out "$tmp/room-out"
row "\`build\`, the room of 16 photos with a lens k_sd on every photo" "$VPMAP" build "$tmp/room-16-lens.json" --out "$tmp/room-out"
row "\`build\`, the room of 16 photos with a principal point prior on every photo" "$VPMAP" build "$tmp/room-16-priors.json" --out "$tmp/room-out"
row "\`build\`, a room of 11 photos, 1078 objects in all (over the limit)" "$VPMAP" build "$tmp/room-over.json" --out "$tmp/room-out"
# A footprint of 1,000 vertices (the limit): the synthetic scene's chair clicked as an ellipse of
# 1,000 points, alone in one photo and added to the bundled room's first photo (before
# 2026-11-30 its block of the fit was dense: 20 s at 300 vertices, 75-129 s at 1,000).
"$VPMAP" synth --seed 3 -o "$tmp/fp.json" > /dev/null
python3 - "$tmp" <<'PY'
import json, math, sys
tmp = sys.argv[1]
def ellipse(cx, cy, a, b, n=1000):
    return [[cx + a * math.cos(2 * math.pi * k / n), cy + b * math.sin(2 * math.pi * k / n)] for k in range(n)]
scene = json.load(open(f"{tmp}/fp.json"))
chair = next(o for o in scene["objects"] if "footprint" in o)
fp = chair["footprint"]
pts = ellipse(sum(p[0] for p in fp) / len(fp), sum(p[1] for p in fp) / len(fp), 120, 50)
chair["footprint"] = pts
chair["top"] = {"above": 0, "point": [pts[0][0], pts[0][1] - 400]}
json.dump(scene, open(f"{tmp}/fp1000.json", "w"))
room = json.load(open("examples/room.json"))
pts = ellipse(500, 1000, 80, 30)
room["photos"][0]["objects"].append({"name": "table", "footprint": pts, "top": {"above": 0, "point": [pts[0][0], pts[0][1] - 150]}})
json.dump(room, open(f"{tmp}/room-fp1000.json", "w"))
PY
row "\`build\`, a footprint of 1,000 vertices (the limit; 75-129 s before 2026-11-30)" "$VPMAP" build "$tmp/fp1000.json" --out "$tmp/fp-out"
row "\`build\`, the bundled room with a footprint of 1,000 vertices added" "$VPMAP" build "$tmp/room-fp1000.json" --out "$tmp/fp-out"
echo

# The server's cases (issue 40: /api/propose, the photo store, room builds and plans on the
# server): `vpmap serve` on a free loopback port, each request timed and its peak memory read
# from /proc (scripts/limits_server.py).
echo "The server's cases (\`vpmap serve\`, one request at a time on a fresh connection; the peak is the"
echo "server process's resident memory at its highest during the request):"
echo
python3 scripts/limits_server.py "$VPMAP" "$tmp"
echo

# Memory a cell takes: the office map.json planned on at two resolutions by each planner; the
# slope of peak memory against cells removes what does not grow with the grid. The grid's size at a
# resolution comes from the refusal at 0.0007 m, which names it (cells scale as 1 / resolution^2).
read -r w0 h0 < <("$VPMAP" plan "$map" --resolution 0.0007 --from=1.1,1.7 --to=0.2,5 2>&1 \
  | grep -o 'a grid of [0-9]* x [0-9]*' | awk '{print $4, $6}')
cells_at() { awk -v w="$w0" -v h="$h0" -v r="$1" 'BEGIN { printf "%d", (w * 0.0007 / r) * (h * 0.0007 / r) }'; }
kib_at() {
  /usr/bin/time -f '%M' -o "$tmp/time" "$VPMAP" plan "$map" --resolution "$1" --planner "$2" \
    --from=1.1,1.7 --to=0.2,5 > /dev/null
  tail -n 1 "$tmp/time"
}
c1=$(cells_at 0.004)
c2=$(cells_at 0.002)
echo "Memory a grid cell takes: the office map.json rasterised, inflated and planned on at 0.004 m"
echo "(about $c1 cells) and 0.002 m (about $c2 cells) a cell; vpmap_plan::grid::BYTES_PER_CELL is" \
  "$(grep -o 'BYTES_PER_CELL: usize = [0-9]*' crates/vpmap-plan/src/cell.rs | awk '{print $4}')."
echo
echo "| planner | peak at 0.004 m | peak at 0.002 m | bytes a cell |"
echo "|---|---|---|---|"
for planner in astar astar-ps theta-star optimal mbpp mbpp-closer; do
  k1=$(kib_at 0.004 "$planner")
  k2=$(kib_at 0.002 "$planner")
  echo "| $planner | $((k1 / 1024)) MB | $((k2 / 1024)) MB | $(( (k2 - k1) * 1024 / (c2 - c1) )) |"
done

# The same with every reachable cell expanded: an open Moving AI map whose goal is walled in
# (no path), at 2000 x 2000 and 4000 x 4000 cells.
write_open() {
  local n=$1
  printf 'type octile\nheight %d\nwidth %d\nmap\n' "$n" "$n"
  local row
  row=$(printf '.%.0s' $(seq 1 "$n"))
  for ((y = 0; y < n - 3; y++)); do printf '%s\n' "$row"; done
  printf '%s@@@\n%s@.@\n%s@.@\n' "${row:3}" "${row:3}" "${row:3}"
}
write_open 2000 > "$tmp/open2000.map"
write_open 4000 > "$tmp/open4000.map"
open_kib() {
  /usr/bin/time -f '%M' -o "$tmp/time" "$VPMAP" plan "$tmp/open$1.map" --planner "$2" \
    --from 0,0 --to "$(($1 - 2)),$(($1 - 2))" > /dev/null 2>&1 || true
  tail -n 1 "$tmp/time"
}
echo
echo "Every cell expanded (an open map, the goal walled in), 2000 x 2000 and 4000 x 4000 cells:"
echo
echo "| planner | peak at 2000 x 2000 | peak at 4000 x 4000 | bytes a cell |"
echo "|---|---|---|---|"
for planner in astar theta-star optimal mbpp; do
  k1=$(open_kib 2000 "$planner")
  k2=$(open_kib 4000 "$planner")
  echo "| $planner | $((k1 / 1024)) MB | $((k2 / 1024)) MB | $(( (k2 - k1) * 1024 / (4000 * 4000 - 2000 * 2000) )) |"
done
echo
echo "(Theta* stops at its line-of-sight budget on these maps, an error; the others answer \"no path\".)"
