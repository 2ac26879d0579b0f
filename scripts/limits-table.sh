#!/usr/bin/env bash
# Re-measures the inputs of docs/limits.md "Measured" on this machine: wall time, peak resident
# memory and the answer of `vpmap` for each, and the memory a grid cell takes (the figure behind
# `vpmap_plan::grid::BYTES_PER_CELL`). Prints a Markdown table.
#
#   bash scripts/limits-table.sh            # builds the release binary first
#   VPMAP=path/to/vpmap bash scripts/limits-table.sh
#
# Needs GNU time (`/usr/bin/time`, Debian package `time`) for peak memory. Writes only to a
# temporary folder, removed at the end.
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
