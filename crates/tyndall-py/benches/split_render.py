"""Splitting a render, measured (issue 13's targets), on the demo at
1280×720, 4 spp: the CLI's render time (its own report), Scene.render in Python, tyndall.distributed.render on a
local two-worker Ray cluster (2 tiles), render_part + merge_parts costs,
and the checkpoint write time. Medians of 3 runs, all in one run of this
script. Run from the repository root, after `cargo build --release` and
`pip install ./crates/tyndall-py ray`:

    python crates/tyndall-py/benches/split_render.py
"""
import os
import re
import statistics
import subprocess
import time

import ray
import tyndall
import tyndall.distributed as dist

BIN = "target/release/tyndall"
W, H, SPP = 1280, 720, 4
runs = 3

def cli():
    out = subprocess.run([BIN, "render", "--width", str(W), "--height", str(H), "--spp", str(SPP), "--threads", "2", "-o", "/tmp/b13.exr"], capture_output=True, text=True, check=True).stderr
    return float(re.search(r" in ([0-9.]+) s:", out).group(1))

scene = tyndall.demo()
def py():
    t = time.perf_counter(); scene.render(width=W, height=H, spp=SPP, threads=2); return time.perf_counter() - t

ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
def ray2():
    t = time.perf_counter(); dist.render(scene, tiles=2, width=W, height=H, spp=SPP); return time.perf_counter() - t
ray2()  # warm the workers
c = [cli() for _ in range(runs)]
p = [py() for _ in range(runs)]
r = [ray2() for _ in range(runs)]
parts = [scene.render_part(tile=(i, 2), width=W, height=H, spp=SPP, threads=2) for i in range(2)]
m = []
for _ in range(runs):
    t = time.perf_counter(); tyndall.merge_parts(parts); m.append(time.perf_counter() - t)
med = statistics.median
print(f"CLI render (its report): {med(c):.2f} s {c}")
print(f"Python Scene.render: {med(p):.2f} s {p}  ratio {med(p)/med(c):.3f}")
print(f"Ray, 2 tiles, 2 workers (warm cluster): {med(r):.2f} s {r}  ratio to CLI {med(r)/med(c):.3f}")
print(f"merge_parts of 2 parts: {med(m):.3f} s; part size {len(parts[0])/1e6:.1f} MB")

def cli_ckpt():
    if os.path.exists("/tmp/b13.ckpt"): os.remove("/tmp/b13.ckpt")
    out = subprocess.run([BIN, "render", "--width", str(W), "--height", str(H), "--spp", str(SPP), "--threads", "2", "--checkpoint", "/tmp/b13.ckpt", "--checkpoint-every", "0s", "-o", "/tmp/b13c.exr"], capture_output=True, text=True, check=True).stderr
    return float(re.search(r" in ([0-9.]+) s:", out).group(1))
k = [cli_ckpt() for _ in range(runs)]
per_write = (med(k) - med(c)) / (SPP - 1)
print(f"CLI with a checkpoint after every pass ({SPP-1} writes): {med(k):.2f} s {k}; per write {per_write:.3f} s; at one a minute {100*per_write/60:.2f} %")
