#!/usr/bin/env bash
# Remakes the window screenshots in assets/ (docs/gui.md shows them).
# Needs a display: run under `xvfb-run -a -s "-screen 0 1600x1000x24"` on a
# machine without one. Existing files are replaced only here, on purpose:
# the app itself never overwrites a file.
set -euo pipefail
bin=$(realpath "${ONEBLOCK:-target/release/oneblock}")
out=$(cd "$(dirname "$0")" && pwd)
shots=(
  "fig3b - gui-fig3b.png"
  "fig3a - gui-fig3a.png"
  "creep - gui-creep.png"
  "intermittent plane gui-plane-intermittent.png"
  "chaos block gui-block-chaos.png"
  "fig4 bifurcation gui-bifurcation-fig4.png"
  "chaos return-map gui-return-map-chaos.png"
  "creep time-series gui-time-series-creep.png"
  "intermittent events gui-events-intermittent.png"
  "chaos numerics gui-numerics-chaos.png"
  "fig4 phase gui-phase-fig4.png"
  "intermittent events gui-events-intermittent.svg"
  "intermittent - gui-projector.png --font-scale 1.5 --hide-panel --size 1024x768"
  "fig3a bifurcation gui-subcritical-fig3a.png --session SESSIONS/fig3a-subcritical.json"
  "- phase gui-phase-multistable.png --session SESSIONS/phase-multistable.json"
  "- phase gui-generalised-flip.png --session SESSIONS/generalised-flip.json"
)
# A neutral working directory: the export folder field shows it.
work=/tmp/oneblock
mkdir -p "$work"
cd "$work"
for s in "${shots[@]}"; do
  read -r preset view file extra <<<"$s"
  extra=${extra//SESSIONS/$out/sessions}
  args=(gui --screenshot "$file")
  # 1280x800 unless the shot names its own size.
  [[ "${extra:-}" == *--size* ]] || args+=(--size 1280x800)
  # "-": no preset (the session gives the parameters).
  [ "$preset" != "-" ] && args+=(--preset "$preset")
  [ "$view" != "-" ] && args+=(--view "$view")
  # shellcheck disable=SC2206 # extra flags, split on purpose
  [ -n "${extra:-}" ] && args+=($extra)
  rm -f "$file"
  "$bin" "${args[@]}"
  mv -f "$file" "$out/$file"
done
# The seeded diagram's hysteresis at kappa = 10 is a figure (headless).
rm -f figure-seeded-hysteresis.png
"$bin" figure --view bifurcation --session "$out/sessions/seeds-16.json" \
  --kappa 10 --gamma 6.5 --nu 1e-3 --theta-nu 1.40 \
  --theta-nu-from 1.30 --theta-nu-to 1.46 --out figure-seeded-hysteresis.png
mv -f figure-seeded-hysteresis.png "$out/figure-seeded-hysteresis.png"
