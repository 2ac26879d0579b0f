#!/usr/bin/env python3
"""The server's hostile cases of issue 40, measured on a running `vpmap serve` (release build).

Started by `scripts/limits-table.sh` (or alone: `python3 scripts/limits_server.py path/to/vpmap
TMPDIR`). Starts the server on a free loopback port, sends each request on a fresh connection and
prints a Markdown table: the request, its answer's status, the wall time from sending it to
reading the whole answer, and the server's peak resident memory during it (`VmHWM` of the server
process, reset before each request through `/proc/PID/clear_refs`), with its resident memory
before. Writes only to TMPDIR. Linux only (`/proc`).
"""

import http.client
import json
import struct
import subprocess
import sys
import time
import zlib


def png(path, side, depth, pattern):
    """A `side` x `side` PNG: 8-bit grey or 16-bit RGBA; `pattern` "checker" (squares of 32 px,
    the proposals' worst case: thousands of segments and corners) or "grey"."""
    colour = 0 if depth == 8 else 6
    bytes_per_px = 1 if depth == 8 else 8
    rows = []
    if pattern == "checker":
        for parity in (0, 1):
            row = bytearray()
            for x in range(side):
                v = 40 if ((x // 32) + parity) % 2 else 215
                row += bytes([v]) * bytes_per_px
            rows.append(b"\0" + bytes(row))
    else:
        rows = [b"\0" + bytes([128]) * (side * bytes_per_px)] * 2

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    z = zlib.compressobj(9)
    idat = b"".join(z.compress(rows[(y // 32) % 2]) for y in range(side)) + z.flush()
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", side, side, depth, colour, 0, 0, 0)))
        f.write(chunk(b"IDAT", idat))
        f.write(chunk(b"IEND", b""))
    return path


def status_kib(pid, field):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return 0


class Server:
    def __init__(self, vpmap):
        self.proc = subprocess.Popen(
            [vpmap, "serve", "--port", "0"],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        deadline = time.time() + 20
        self.port = None
        while time.time() < deadline and self.port is None:
            line = self.proc.stdout.readline()
            if "http://" in line:
                self.port = int(line.split("http://")[1].split("/")[0].rsplit(":", 1)[1])
        if self.port is None:
            self.proc.kill()
            raise SystemExit("limits_server.py: the server printed no address within 20 s")

    def request(self, path, body, content_type):
        """(status, answer bytes, seconds, peak MB during the request, resident MB before)."""
        pid = self.proc.pid
        before = status_kib(pid, "VmRSS")
        with open(f"/proc/{pid}/clear_refs", "w") as f:
            f.write("5")
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=120)
        start = time.time()
        conn.request("POST", path, body=body, headers={"Content-Type": content_type})
        answer = conn.getresponse()
        data = answer.read()
        seconds = time.time() - start
        conn.close()
        peak = status_kib(pid, "VmHWM")
        return answer.status, data, seconds, peak / 1024, before / 1024

    def stop(self):
        self.proc.terminate()
        self.proc.wait(10)


def first_line(data):
    try:
        value = json.loads(data)
    except ValueError:
        return data[:100].decode(errors="replace")
    if isinstance(value, dict) and "error" in value:
        return "error: " + str(value["error"])[:100]
    return "ok"


def free_points(answer):
    """Two free cells of a build answer's occupancy grid far apart, as map points."""
    import base64

    occ = answer["occupancy"]
    pgm = base64.b64decode(occ["pgm_base64"])
    w, h = occ["width"], occ["height"]
    pixels = pgm[len(pgm) - w * h :]
    free = [(i % w, i // w) for i in range(0, w * h, 7) if pixels[i] == 254]
    a = min(free, key=lambda c: c[0] + c[1])
    b = max(free, key=lambda c: c[0] + c[1])
    res, (ox, oy) = occ["resolution"], occ["origin"]

    def point(c):
        return [ox + (c[0] + 0.5) * res, oy + (h - 1 - c[1] + 0.5) * res]

    return point(a), point(b)


def main():
    vpmap, tmp = sys.argv[1], sys.argv[2]
    vps = [[-2000.0, 450.0], [4000.0, 480.0], [800.0, 9000.0]]
    server = Server(vpmap)
    rows = []

    def row(what, path, body, content_type="application/json"):
        status, data, seconds, peak, before = server.request(path, body, content_type)
        rows.append(
            f"| {what} | {status} | {seconds:.2f} s | {peak:.0f} MB (from {before:.0f}) | "
            f"{first_line(data).replace('|', '/')} |"
        )
        return status, data

    def photo(path):
        with open(path, "rb") as f:
            return f.read()

    def photo_then_propose(what, path, propose_what):
        """`/api/photo` with the PNG at `path`, then, when kept, `/api/propose` on it."""
        status, data = row(what, "/api/photo", photo(path), "image/png")
        if status == 200:
            pid = json.loads(data)["id"]
            body = json.dumps({"photo": pid, "vanishing_points": vps, "max_proposals": 10})
            row(propose_what, "/api/propose", body)

    try:
        for side in (1000, 2000):
            p = png(f"{tmp}/checker{side}.png", side, 8, "checker")
            photo_then_propose(
                f"`/api/photo`, a {side} x {side} checkerboard PNG", p,
                "`/api/propose` on it (was 29 s at 1000, 130 s at 2000)",
            )
        for n in range(4):
            p = png(f"{tmp}/rgba16-{n}.png", 4000, 16, "grey")
            row(f"`/api/photo`, 16-bit RGBA 4000 x 4000 PNG {n + 1} of 4 (four left the server at 706 MB)", "/api/photo", photo(p), "image/png")
        p = png(f"{tmp}/grey8000.png", 8000, 8, "grey")
        photo_then_propose(
            "`/api/photo`, an 8000 x 8000 photo (the page's largest side)", p,
            "`/api/propose` on it (peaked at 1.75 GB)",
        )
        p = png(f"{tmp}/checker8000.png", 8000, 8, "checker")
        photo_then_propose("`/api/photo`, an 8000 x 8000 checkerboard PNG", p, "`/api/propose` on it")
        row("`/api/detect`, the same 8000 x 8000 checkerboard", "/api/detect", photo(p), "image/png")
        with open(f"{tmp}/room-16.json") as f:
            room = f.read()
        status, data = row("`/api/build`, a room of 16 photos, 992 objects in all (a 503 for 50 s before)", "/api/build", room)
        if status == 200:
            start, goal = free_points(json.loads(data))
            body = json.dumps({"scene": json.loads(room), "start": start, "goal": goal})
            row("`/api/plan` across that room (18.7 s before)", "/api/plan", body)
        with open(f"{tmp}/room-over.json") as f:
            row("`/api/build`, a room of 11 photos, 1078 objects in all (over the limit)", "/api/build", f.read())
    finally:
        server.stop()
    print("| request | status | wall time | server's peak memory | answer |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
