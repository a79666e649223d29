#!/usr/bin/env python3
"""Tables of docs/results/session-config/run.sh's output folders (docs/results/session-config.md).

Usage: table.py OUT... ; prints markdown: the session default per scene, the budgets, the streams
while a calibration ran, and the restarted server.
"""
import glob
import json
import os
import re
import statistics
import sys


def load(path):
    with open(path) as f:
        return json.load(f)


def budget_cell(b):
    if not b:
        return "-"
    note = b.get("note", "")
    return note if note else "both met"


def scene_rows(out):
    for times in sorted(glob.glob(os.path.join(out, "*.times.txt"))):
        scene = os.path.basename(times)[: -len(".times.txt")]
        words = open(times).read().split()
        load_s, first_s = float(words[2]), float(words[4])
        info = load(os.path.join(out, scene + ".session.json"))
        field = info.get("field", {})
        cal, b = field.get("calibration", {}), field.get("budget", {})
        default = load(os.path.join(out, scene + ".default.json"))
        during = [load(p) for p in glob.glob(os.path.join(out, scene + ".during.*.json"))]
        yield scene, load_s, first_s, cal, b, default, during


def main(outs):
    print("| scene | load s | first 1080p frame s | calibration | switch after s | chosen | "
          "calibrated ms | stream GPU ms/frame | of it field ms | fps | FLIP (calibration) | "
          "mean/ref (calibration) | budget, light |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows = [r for out in outs for r in scene_rows(out)]
    for scene, load_s, first_s, cal, b, default, during in rows:
        print(f"| {scene} | {load_s:.2f} | {first_s:.2f} | {cal.get('state', '?')[6:].lower()} "
              f"{cal.get('candidates_done', 0)}/{cal.get('candidates', 0)} | "
              f"{cal.get('seconds', 0):.1f} | {b.get('configuration', '-')} | "
              f"{b.get('cost_ms', 0):.2f} | {default['gpu_ms_mean']:.2f} | "
              f"{default['gi_update_ms_mean']:.2f} | {default['fps']:.0f} | "
              f"{b.get('flip', 0):.4f} ± {b.get('flip_noise', 0):.4f} | "
              f"{b.get('mean_ratio', 0):.3f} ± {b.get('mean_ratio_noise', 0):.3f} | "
              f"{budget_cell(b)} |")
    print("\nStreaming 1920x1080 while the calibration ran (2 s runs) and after it:\n")
    print("| scene | runs | fps while calibrating (min / median) | fps after | GPU ms/frame while "
          "(median) | after |")
    print("|---|---|---|---|---|---|")
    for scene, _, _, _, _, default, during in rows:
        fps = [d["fps"] for d in during if d["frames"] > 0]
        gpu = [d["gpu_ms_mean"] for d in during if d["frames"] > 0]
        if not fps:
            continue
        print(f"| {scene} | {len(fps)} | {min(fps):.0f} / {statistics.median(fps):.0f} | "
              f"{default['fps']:.0f} | {statistics.median(gpu):.2f} | "
              f"{default['gpu_ms_mean']:.2f} |")
    print("\n| scene | budget ms | chosen | calibrated ms | stream GPU ms/frame | fps | FLIP "
          "(calibration) | mean/ref (calibration) | report |")
    print("|---|---|---|---|---|---|---|---|---|")
    for out in outs:
        for params in sorted(glob.glob(os.path.join(out, "*.budget*.params.json")),
                             key=lambda p: (p.split(".budget")[0],
                                            float(re.search(r"budget([0-9.]+)", p).group(1)))):
            scene = os.path.basename(params).split(".budget")[0]
            budget = re.search(r"budget([0-9.]+)\.params", params).group(1)
            b = load(params).get("budget", {})
            s = load(params.replace(".params.json", ".json"))
            print(f"| {scene} | {budget} | {b.get('configuration', '-')} | "
                  f"{b.get('cost_ms', 0):.2f} | {s['gpu_ms_mean']:.2f} | {s['fps']:.0f} | "
                  f"{b.get('flip', 0):.4f} ± {b.get('flip_noise', 0):.4f} | "
                  f"{b.get('mean_ratio', 0):.3f} ± {b.get('mean_ratio_noise', 0):.3f} | "
                  f"{budget_cell(b)} |")
    for out in outs:
        for restart in glob.glob(os.path.join(out, "restart.*.load.json")):
            cal = load(restart).get("field", {}).get("calibration", {})
            b = load(restart).get("field", {}).get("budget", {})
            print(f"\nRestarted server, {os.path.basename(restart)[8:-10]}: calibration "
                  f"{cal.get('state')}, from_cache {cal.get('from_cache')}, chosen at load: "
                  f"{b.get('configuration', '-')}")


if __name__ == "__main__":
    main(sys.argv[1:])
