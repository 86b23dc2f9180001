#!/usr/bin/python3
"""Issue 17's headline from scripts/adaptive-sweep.sh's frames.

adaptive_sweep_table.py ERRORS [--png-reference DIR] [HOST_DIR ...]
  ERRORS    frames rendered as EXR with their `svo compare --json` against the
            references (NAME.compare.json): the relMSE of each frame; its
            NAME.json (`svo render --json`) are the first host's times
  DIR       PNGs of the same frames on the host that rendered ERRORS: each
            HOST_DIR's PNGs are compared with them, to show that the hosts
            rendered the same images
  HOST_DIR  frames of the same command lines on another host (NAME.json,
            NAME.png): that host's times
Prints a Markdown table per host: for each scene and material, the best
speed-up of adaptive over forward shading at equal relMSE (forward's time
interpolated log-log on its sweep at the adaptive frame's relMSE; ">=" where
the adaptive frame is below forward's lowest error, then forward's slowest
frame is the comparison), per variance mode.
"""
import json
import math
import os
import re
import sys

import numpy as np
import OpenImageIO as oiio


def frames(directory, suffix):
    out = {}
    for name in sorted(os.listdir(directory)):
        m = re.match(r"(\w+)-(\w+)-(forward|bound|measured)-([0-9.]+)" + re.escape(suffix) + "$", name)
        if m:
            out[(m[1], m[2], m[3], float(m[4]))] = os.path.join(directory, name)
    return out


def forward_ms_at(points, relmse):
    """points: [(relmse, ms)] of the forward sweep; the time at `relmse`, and
    whether it is a bound (">=" below the sweep's lowest error, "<=" above its
    highest)."""
    pts = sorted(points)
    if relmse <= pts[0][0]:
        return pts[0][1], ">="
    if relmse >= pts[-1][0]:
        return pts[-1][1], "<="
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= relmse <= e1:
            f = (math.log(relmse) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), ""
    raise AssertionError


def read_rgb(path):
    image = oiio.ImageBuf(path)
    return np.asarray(image.get_pixels(oiio.UINT8))[..., :3].astype(int)


def main():
    args = sys.argv[1:]
    png_reference = None
    if "--png-reference" in args:
        at = args.index("--png-reference")
        png_reference = args[at + 1]
        del args[at:at + 2]
    errors_dir, hosts = args[0], args
    hosts[0] = errors_dir
    relmse = {k: json.load(open(p))["relmse"] for k, p in frames(errors_dir, ".compare.json").items()}
    configs = sorted({(s, m) for s, m, _, _ in relmse})
    for h, host in enumerate(hosts):
        runs = {k: json.load(open(p)) for k, p in frames(host, ".json").items()}
        device = next(iter(runs.values()))["device"]
        print(f"### {device} ({host})\n")
        if h > 0 and png_reference and frames(host, ".png"):
            worst, off = 0, 0
            for k, p in frames(host, ".png").items():
                a, b = read_rgb(p), read_rgb(frames(png_reference, ".png")[k])
                d = np.abs(a - b)
                worst = max(worst, int(d.max()))
                off = max(off, int((d.max(axis=-1) > 2).sum()))
            print(f"Same images as {png_reference}: largest 8-bit difference {worst}, at most {off} pixels "
                  f"more than 2 levels off in one frame.\n")
        print("| scene | material | forward ms (8 / 128 spp) | best adaptive, Eq. 9 bound | "
              "best adaptive, measured variance | adaptive frame: trace / bandwidth / shading ms |")
        print("|---|---|---|---|---|---|")
        for scene, material in configs:
            fwd = [(relmse[k], runs[k]["ms"]) for k in runs if k[:3] == (scene, material, "forward")]
            fwd_ms = {k[3]: runs[k]["ms"] for k in runs if k[:3] == (scene, material, "forward")}
            cells, split = [], ""
            for mode in ("bound", "measured"):
                best = None
                for k in runs:
                    if k[:3] != (scene, material, mode):
                        continue
                    t, bound = forward_ms_at(fwd, relmse[k])
                    speed = t / runs[k]["ms"]
                    if bound != "<=" and (best is None or speed > best[0]):
                        best = (speed, bound, k[3], runs[k], relmse[k])
                if best is None:
                    cells.append("none in the sweep")
                    continue
                speed, bound, tau, run, err = best
                cells.append(f"{bound}{speed:.2f}x (tau {tau:g}: {run['ms']:.1f} ms, relMSE {err:.3g})")
                if mode == "measured":
                    passes = {p["name"]: p["ms"] for p in run.get("passes", [])}
                    a = run.get("adaptive", {})
                    split = (f"{passes.get('trace', float('nan')):.1f} / {a.get('bandwidth_ms', float('nan')):.1f} / "
                             f"{a.get('shading_ms', float('nan')):.1f}")
            print(f"| {scene} | {material} | {fwd_ms.get(8.0, float('nan')):.1f} / {fwd_ms.get(128.0, float('nan')):.1f} | "
                  f"{cells[0]} | {cells[1]} | {split} |")
        print()


if __name__ == "__main__":
    main()
