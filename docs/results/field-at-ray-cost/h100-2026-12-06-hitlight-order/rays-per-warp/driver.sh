#!/usr/bin/env bash
# The session driver this call ran (kept as its record; .devcarry/variants/NAME held each variant's build): hit light with several rays of each probe per warp.
set -uo pipefail
mkdir -p /tmp/v
bash docs/results/field-at-ray-cost/variants.sh /tmp/v 3 base q2 q4
cat /tmp/v/device.txt
tar czf "$OUT/v20.tgz" -C /tmp v
