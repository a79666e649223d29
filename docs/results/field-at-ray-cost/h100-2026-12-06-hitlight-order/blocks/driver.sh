#!/usr/bin/env bash
# The session driver this call ran (kept as its record; .devcarry/variants/NAME held each variant's build): hit-light ray-major order with probes in 3D tiles.
set -uo pipefail
mkdir -p /tmp/v
bash docs/results/field-at-ray-cost/variants.sh /tmp/v 3 base t424 t822 t222
cat /tmp/v/device.txt
tar czf "$OUT/v15.tgz" -C /tmp v
