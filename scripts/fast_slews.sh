#!/usr/bin/env bash
# Fast slews (issue 16 item 4; seed 004 Table 1.3: acquire at up to 4 deg/s, track at up to
# 10 deg/s): for each slew rate and exposure, `simulate` a 30 s slew of the sample camera
# (rawlogs/slew_2dps.ini's: 15 deg, 512 px, 25 mm aperture, 8-bit) about a body axis near the
# camera's y with a small tumble, and `replay` it four ways:
#   tracking          gyro + filter (rawlogs/tracker.ini): lost-in-space once, then tracking
#   lis+gyro          every frame lost-in-space with the gyro's rate for the streaks
#                     ([filter] enabled = false): acquisition with a gyro
#   lis               every frame lost-in-space, no rate (the GYRO label ignored): blind
#                     acquisition, streaks from their shapes
#   gyroless          the gyroless filter (rawlogs/gyroless_tracker.ini, its rate prior
#                     rate_sigma_deg_s set to the slew rate): lost-in-space, then the rate
#                     from the fixes
# The tracker's exposure_s is the scenario's. Prints a Markdown table (solved %, tracking %,
# misidentified stars, wrong valid outputs, cross-boresight error RMS) and writes it to
# OUT/fast_slews.md.
#
# usage: scripts/fast_slews.sh [--rates "4 10"] [--exposures "0.1 0.05 0.02"] [--seconds 30]
#                              [--out DIR] [--build DIR]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
rates="4 10"
exposures="0.1 0.05 0.02"
seconds=30
out="$repo/out/fast_slews"
build="$repo/build"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --rates) rates=$2; shift 2 ;;
    --exposures) exposures=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    -h|--help) sed -n 2,19p "$0"; exit 0 ;;
    *) echo "fast_slews.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
st="$build/app/startracker"
[[ -x "$st" ]] || { echo "fast_slews.sh: $st not built" >&2; exit 2; }
mkdir -p "$out"
table="$out/fast_slews.md"
{
  echo "| rate [deg/s] | exposure [s] | streak [px] | mode | solved % | tracking % | misidentified | wrong valid | cross RMS [\"] |"
  echo "|---|---|---|---|---|---|---|---|---|"
} >"$table"

# One replay's row from its summary.
row() {
  local rate=$1 exp=$2 mode=$3 log=$4
  local solved tracking misid wrong cross streak
  solved=$(sed -n 's/^frames: [0-9]*, solved \([0-9.]*\) %.*/\1/p' "$log")
  tracking=$(sed -n 's/.*tracking \([0-9.]*\) %.*/\1/p' "$log" | head -1)
  misid=$(sed -n 's/.*, \([0-9]*\) misidentified.*/\1/p' "$log")
  wrong=$(sed -n 's/^integrity (vs GROUND_TRUTH.*): \([0-9]*\) wrong valid outputs.*/\1/p' "$log")
  cross=$(sed -n 's/^  cross-boresight  RMS *\([0-9.]*\).*/\1/p' "$log")
  streak=$(awk -v r="$rate" -v e="$exp" 'BEGIN { printf "%.0f", r * e * 512 / 15 }')
  echo "| $rate | $exp | $streak | $mode | ${solved:--} | ${tracking:--} | ${misid:--} | ${wrong:--} | ${cross:--} |" | tee -a "$table"
}

for rate in $rates; do
  for exp in $exposures; do
    name="slew_${rate}dps_${exp}s"
    ini="$out/$name.ini"
    sed -e "s/^duration_s .*/duration_s     = $seconds/" -e "s/^frame_rate_hz .*/frame_rate_hz  = 5/" \
        -e "s/^rate_deg_s = .*/rate_deg_s = 0.3 $rate 0.2/" -e "s/^exposure_s .*/exposure_s           = $exp/" \
        "$repo/rawlogs/slew_2dps.ini" >"$ini"
    echo "fast_slews: $name" >&2
    "$st" simulate -q "$ini" -o "$out/$name.rawlog" --force >/dev/null
    for mode in tracking lis+gyro lis gyroless; do
      cfg="$out/${name}_$mode.ini"
      case $mode in
        tracking) sed "s/^exposure_s .*/exposure_s     = $exp/" "$repo/rawlogs/tracker.ini" >"$cfg" ;;
        lis+gyro) sed -e "s/^exposure_s .*/exposure_s     = $exp/" -e 's/^\[filter\]/[filter]\nenabled = false/' \
                      "$repo/rawlogs/tracker.ini" >"$cfg" ;;
        lis) { sed "s/^exposure_s .*/exposure_s     = $exp/" "$repo/rawlogs/tracker.ini"
               printf '\n[navigator]\ngyro_label = NO_GYRO\n'; } >"$cfg" ;;
        gyroless) sed -e "s/^exposure_s .*/exposure_s     = $exp/" -e "s/^rate_sigma_deg_s = .*/rate_sigma_deg_s = $rate/" \
                      "$repo/rawlogs/gyroless_tracker.ini" >"$cfg" ;;
      esac
      log="$out/${name}_$mode.log"
      "$st" replay -q "$out/$name.rawlog" --config "$cfg" >"$log" 2>&1 || true
      row "$rate" "$exp" "$mode" "$log"
    done
  done
done
echo "fast_slews: table in $table" >&2
