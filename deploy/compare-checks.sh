#!/usr/bin/env bash
# Compares two folders written by deploy/render-checks.sh (e.g. lavapipe vs the H100) image by
# image with ddgi-compare and prints a markdown table. Usage: deploy/compare-checks.sh A B
set -euo pipefail
a="$1"
b="$2"
compare=${DDGI_COMPARE:-ddgi-compare}
echo "| image | RMSE | PSNR (dB) | SSIM | mean FLIP |"
echo "|---|---|---|---|---|"
for ref in "$a"/*.exr; do
  name=$(basename "$ref")
  [ -f "$b/$name" ] || continue
  json=$("$compare" "$ref" "$b/$name" --json)
  python3 - "$name" "$json" <<'PY'
import json, sys
name, j = sys.argv[1], json.loads(sys.argv[2])
psnr = j.get("psnr_db")
print(f"| {name} | {j['rmse']:.5f} | {'inf' if psnr is None else f'{psnr:.1f}'} | {j['ssim']:.4f} | {j['flip_mean']:.4f} |")
PY
done
