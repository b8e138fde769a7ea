#!/usr/bin/env bash
# LAZ decoding speed: our decoder against laz-perf (npm, WebAssembly) on the same files in
# the same run. laz-perf is installed into a scratch folder for this script only; it is
# never part of the product. Usage: bash bench/laz_ratio.sh [build-dir]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
data="$root/../shared/data"
scratch="${TMPDIR:-/tmp}/strata-lazperf"
command -v node >/dev/null || { echo "laz_ratio.sh: needs node and npm" >&2; exit 1; }
if [ ! -d "$scratch/node_modules/laz-perf" ]; then
    mkdir -p "$scratch"
    echo "installing laz-perf from the npm registry into $scratch" >&2
    (cd "$scratch" && npm install --silent --no-audit --no-fund laz-perf >/dev/null)
fi
cat > "$scratch/time.mjs" <<'JS'
import { createLazPerf } from 'laz-perf';
import { readFileSync } from 'node:fs';
const lazperf = await createLazPerf();
for (const path of process.argv.slice(2)) {
    const bytes = readFileSync(path);
    const filePtr = lazperf._malloc(bytes.length);
    lazperf.HEAPU8.set(bytes, filePtr);
    let best = Infinity, count = 0;
    const probe = new lazperf.LASZip();
    probe.open(filePtr, bytes.length);
    count = probe.getCount();
    const pointPtr = lazperf._malloc(probe.getPointLength());
    probe.delete();
    // Small files are decoded many times per run, each time from open (like our seek to 0).
    const repeat = count < 100000 ? 200 : 1;
    for (let run = 0; run < 3; run++) {
        const t0 = process.hrtime.bigint();
        for (let r = 0; r < repeat; r++) {
            const laszip = new lazperf.LASZip();
            laszip.open(filePtr, bytes.length);
            for (let i = 0; i < count; i++) { laszip.getPoint(pointPtr); }
            laszip.delete();
        }
        best = Math.min(best, Number(process.hrtime.bigint() - t0) / 1e9 / repeat);
    }
    lazperf._free(pointPtr);
    lazperf._free(filePtr);
    console.log(`laz-perf: ${path}: ${count} points, ${(count / best / 1e6).toFixed(2)} M points/s`);
}
JS
echo "== ours (tests/test_laz decoding_speed, best of 3)"
"$build/tests/test_laz" decoding_speed | grep "LAZ decode speed"
echo "== laz-perf $(node -e "console.log(require('$scratch/node_modules/laz-perf/package.json').version)") (node $(node --version), best of 3)"
(cd "$scratch" && node time.mjs "$data/laz/autzen_trim.laz" "$data/laz-tiles/bcts_3.laz" \
    "$data/laz/1_4_w_evlr.laz")
