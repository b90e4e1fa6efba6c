#!/usr/bin/env bash
# Time to equal error, denoised, Tyndall against Cycles 4.5 with its own
# OIDN, on the shared reference scenes (docs/benchmarks.md, "Denoising and AOVs").
#
#   PEERS=/tmp/peers bash scenes/denoise/side_by_side.sh [scene ...]
#
# PEERS is a set-up copy of ../shared/peers (`bash setup.sh --with-cycles`);
# TYNDALL_OIDN must name the OIDN library; run from the repository root
# after `cargo build --release`. Renders one at a time (2 cores). Tyndall's
# time is the wall time of the whole command (process start, scene build,
# render, OIDN load and denoise, EXR write); Cycles' is its render call
# alone (`time_render_s`, which includes its denoising), so the comparison
# leaves Cycles its start-up.
set -euo pipefail
: "${PEERS:?set PEERS to a set-up copy of ../shared/peers}"
: "${TYNDALL_OIDN:?set TYNDALL_OIDN to the OIDN library folder}"
REPO="$(pwd)"
TARGET="${TARGET:-0.001}"
OUT="${OUT:-/tmp/tyndall-denoise-bench}"
mkdir -p "$OUT"
SCENES=("$@")
if [ ${#SCENES[@]} -eq 0 ]; then
    SCENES=(fog-spot-empty fog-spot-sphere fog-spot-glass-pair cornell-surfaces cornell-surfaces-depth3 fog-room-depth2 fog-room-multi)
fi
for s in "${SCENES[@]}"; do
    ref="$REPO/../shared/reference/$s.exr"
    echo "== $s: Tyndall --denoise"
    (cd "$PEERS" && .venv/bin/python compare.py eqtime --ref "$ref" --target "$TARGET" \
        --spp 1 2 4 8 16 32 --time-source wall --workdir "$OUT/$s-tyndall" \
        --json-out "$OUT/$s-tyndall.json" \
        --cmd "$REPO/target/release/tyndall render $REPO/scenes/reference/$s.toml --spp {spp} --seed 7 --denoise -q -o {out}.exr")
    echo "== $s: Cycles 4.5 + OIDN"
    (cd "$PEERS" && TYNDALL_PEERS="$PEERS" .venv/bin/python compare.py eqtime --ref "$ref" --target "$TARGET" \
        --spp 1 2 4 8 16 32 64 128 --time-source renderer --workdir "$OUT/$s-cycles" \
        --json-out "$OUT/$s-cycles.json" \
        --cmd ".venv-bpy/bin/python $REPO/scenes/denoise/cycles_denoised.py $REPO/../shared/reference/$s.json --spp {spp} --seed 7 --no-png --out {out}")
done
