#!/usr/bin/env python3
"""The table of a deploy/service-bench.sh run, as docs/results/service-bench.md shows it: one
row per stream (SCENE[.FIELDS].SIZE[.web].json), with what the session chose on load where it
chose (the energy calibration's configuration, a time budget's), then the shared-session views
(multi.N.json). Standard library only, so it runs on the GPU host and here alike.

    deploy/service_bench_table.py OUT_DIR
"""
import json
import pathlib
import re
import sys

RUN = re.compile(r"^(?P<session>.+)\.(?P<size>\d+x\d+)(?P<web>\.web)?\.json$")
VIEW = re.compile(r"^multi\.(?P<index>\d+)\.json$")


def load(path):
    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as error:
        sys.exit(f"{path}: cannot read a run's JSON: {error}")


def chosen(session_file):
    """What the session's load chose, e.g. "energy 'paths 1'; budget 'rays 64, emitters 1'"."""
    if not session_file.exists():
        return ""
    field = load(session_file).get("field", {})
    parts = []
    for key in ("energy", "budget"):
        if field.get(key, {}).get("configuration"):
            parts.append(f"{key} '{field[key]['configuration']}'")
    return "; ".join(parts)


def stream_row(out, path, match):
    run = load(path)
    latency = run.get("latency_ms", {})
    row = "| {} | {} | {} | {:.0f} | {:.2f} ({:.2f}) | {:.2f} | {:.0f} | {:.1f} / {:.1f} | {} | {} |"
    return row.format(
        match["session"],
        match["size"],
        "WebSocket" if match["web"] else "gRPC",
        run["fps"],
        run["gpu_ms_mean"],
        run["gi_update_ms_mean"],
        run["encode_ms_mean"],
        run["jpeg_bytes_mean"] / 1024,
        latency.get("p50", float("nan")),
        latency.get("p90", float("nan")),
        run["frames_dropped"],
        chosen(out / f"{match['session']}.session.json"),
    )


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: deploy/service_bench_table.py OUT_DIR")
    out = pathlib.Path(sys.argv[1])
    if not out.is_dir():
        sys.exit(f"{out}: not a directory (deploy/service-bench.sh run's OUT_DIR)")
    runs = [(p, RUN.match(p.name)) for p in sorted(out.glob("*.json"))]
    runs = [(p, m) for p, m in runs if m]
    if not runs:
        sys.exit(f"{out}: no stream results (SCENE.WIDTHxHEIGHT.json)")
    print("| session | size | transport | fps | GPU ms/frame (field update) | JPEG encode ms "
          "| JPEG KB | latency p50 / p90 ms | dropped | chosen on load |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for path, match in runs:
        print(stream_row(out, path, match))
    views = [(int(m["index"]), p) for p in out.glob("multi.*.json") if (m := VIEW.match(p.name))]
    views = [p for _, p in sorted(views)]
    if views:
        fps = [load(p)["fps"] for p in views]
        print(f"\n{len(views)} clients on one session: "
              + ", ".join(f"{f:.0f}" for f in fps) + " fps")


if __name__ == "__main__":
    main()
