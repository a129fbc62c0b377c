#!/usr/bin/env bash
# Writes the demo's outputs (PNG, PSD, ORA, TIFF, layers folder, report without
# timings, a batch) at 1 and 2 threads into DIR, and their SHA-256 sums into
# DIR.sums: run it before and after a change that must not change the look,
# then diff the two .sums files. Usage: scripts/demo-outputs.sh DIR
set -euo pipefail
BIN=${BIN:-$(cd "$(dirname "$0")/.." && pwd)/target/release/grime}
SAMPLE=$(cd "$(dirname "$0")/.." && pwd)/samples/brick-wall-cc0.png
OUT=$1; rm -rf "$OUT"; mkdir -p "$OUT"
for t in 1 2; do
  for demo in facade brick; do
    for ext in png psd ora tif; do
      RAYON_NUM_THREADS=$t $BIN run --demo $demo -q -o "$OUT/$demo-t$t.$ext" ${EXTRA:-}
    done
    RAYON_NUM_THREADS=$t $BIN run --demo $demo -q -o "$OUT/$demo-t$t-l.png" --layers-dir "$OUT/$demo-t$t-layers" --report "$OUT/$demo-t$t-report.json"
    python3 -c "
import json,sys
p=sys.argv[1]; d=json.load(open(p))
def strip(o):
    if isinstance(o,dict): return {k:strip(v) for k,v in o.items() if 'ms' not in k and 'time' not in k and 'second' not in k}
    if isinstance(o,list): return [strip(v) for v in o]
    return o
json.dump(strip(d),open(p,'w'),indent=1,sort_keys=True)" "$OUT/$demo-t$t-report.json"
  done
done
# batch too
mkdir -p "$OUT/bin"; cp "$SAMPLE" "$OUT/bin/a.png"
RAYON_NUM_THREADS=2 $BIN batch "$OUT/bin" -o "$OUT/bout" --format png,psd -q > /dev/null
(cd "$OUT" && find . -type f | sort | xargs sha256sum) > "$OUT.sums"
echo "$(wc -l < "$OUT.sums") files summed into $OUT.sums"
