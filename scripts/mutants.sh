#!/usr/bin/env bash
# Mutation check of the papers' rules (issue 17): each mutant below removes or breaks one
# rule in a scratch copy of the tree, rebuilds only the test executable that should notice,
# runs the named tests and reports which one kills it (KILLED by X) or SURVIVED. A mutant that
# does not compile counts as a failure of this script (it would prove nothing).
#
# Usage: scripts/mutants.sh [--check] [--check-table FILE] [--md FILE] [NAME...]
#   --check   only check that every mutant's sed expression still changes its file (no build;
#             ctest `mutants_expressions_match` runs this so the table does not rot)
#   --check-table FILE
#             refuse a table (docs/mutants.md) with a row older than the file it mutates, a
#             mutant without a row, or a survivor (no build; exit 1, naming each)
#   --md FILE write the result table as Markdown (docs/mutants.md); each row records the
#             commit it was measured at. With NAME... only those rows are replaced, the others
#             kept. Needs a committed tree (the rows must name what they measured).
#   NAME...   run only these mutants
# Exit status: 0 when every mutant is killed (or, with --check, every expression matches).
# Slow (a rebuild per mutant): not part of CI; run it with nice -n 10. The scratch copy lives
# in build-mutants/ of the tree (MUTANTS_DIR overrides), under /work so ccache hits.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
CHECK=0
CHECK_TABLE=""
MD=""
ONLY=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --check) CHECK=1 ;;
    --check-table) CHECK_TABLE="$2"; shift ;;
    --md) MD="$2"; shift ;;
    -h|--help) sed -n 2,19p "$0"; exit 0 ;;
    -*) echo "mutants.sh: unknown option '$1'" >&2; exit 2 ;;
    *) ONLY+=("$1") ;;
  esac
  shift
done

# ---- the mutants: name | file | sed -E expression | test target | gtest filter | rule -----
NAMES=() FILES=() EXPRS=() TARGETS=() FILTERS=() RULES=()
mutant() {
  NAMES+=("$1") FILES+=("$2") EXPRS+=("$3") TARGETS+=("$4") FILTERS+=("$5") RULES+=("$6")
}
ID=st_test_identify
mutant voting-spike-rule sensors/identify/voting.cpp \
  's/std::max\(2, \(n - 1\) - n_smax\)/2/@@s/if \(n_x > n_smax \|\| top.empty\(\)\)/if ((void)n_smax, top.empty())/' \
  $ID 'IdentifyRules.Voting*' \
  "seed 000: n_x > n_smax skips a spike reference; f1 must reach (n-1)-n_smax"
mutant voting-unique-companion sensors/identify/voting.cpp \
  's/if \(found == 1\) seeds/if (found >= 1) seeds/' \
  $ID 'IdentifyRules.Voting*' \
  "seed 000 eq. 15: companion named only when l1 appears once in its slice"
mutant triangle-area-moment sensors/identify/triangle_match.cpp \
  's/if \(std::abs\(fc.area - fo.area\) > tol\[0\] \|\|/if (false \&\&/' \
  $ID 'IdentifyRules.Planar*:IdentifyRules.Spherical*' \
  "seed 001: planar/spherical area and polar moment comparison (both)"
mutant triangle-area-only sensors/identify/triangle_match.cpp \
  's/std::abs\(fc.polar_moment - fo.polar_moment\) > tol\[1\]/false/' \
  $ID 'IdentifyRules.Planar*:IdentifyRules.Spherical*' \
  "seed 001: the polar moment left out (area alone)"
mutant triangle-moment-only sensors/identify/triangle_match.cpp \
  's/std::abs\(fc.area - fo.area\) > tol\[0\] \|\|/false ||/' \
  $ID 'IdentifyRules.Planar*:IdentifyRules.Spherical*' \
  "seed 001: the area left out (polar moment alone)"
mutant liebe-vertex-angle sensors/identify/liebe.cpp \
  's/ \|\| std::abs\(f->phi - phi\) > tphi\)/ || ((void)phi, (void)tphi, false))/' \
  $ID 'IdentifyRules.Liebe*' \
  "seed 003: the angle at the star between its two neighbours"
mutant liebe-image-rim sensors/identify/liebe.cpp \
  's/if \(d2 > rim\) continue;/(void)rim;/' \
  $ID 'IdentifyRules.Liebe*' \
  "seed 003 Initial Estimate: skip a star whose 2nd neighbour is farther than the rim"
mutant nvertex-baselines sensors/identify/nvertex.cpp \
  's/if \(!ctx.angleMatches\(o\[j\], o\[k\], s\[j\], c\)\) return;/(void)0;/' \
  $ID 'IdentifyRules.NVertex*' \
  "seed 004 eq. 6.7: every baseline between the assigned candidates (BC; BC BD CD; B..E), n = 3, 4, 5"
mutant pyramid-fourth-star sensors/identify/pyramid.cpp \
  's/!ctx.angleMatches\(j, r, t\[1\], d\) \|\|//@@s/!ctx.angleMatches\(k, r, t\[2\], d\)\)/false)/' \
  $ID 'IdentifyRules.Pyramid*' \
  "Pyramid (seed 002 ref. 18): the 4th star's angles to the triangle's 2nd and 3rd stars"
mutant handedness-shared sensors/identify/identifier.cpp \
  's/return \(so > 0\) == \(sc > 0\);/return (void)so, (void)sc, true;/' \
  $ID 'IdentifyRules.Mirrored*' \
  "mirror images rejected by the triple product (pyramid, planar, spherical, nvertex)"
mutant handedness-liebe sensors/identify/liebe.cpp \
  's/if \(\(so > 0\) != \(sc > 0\)\) continue;/(void)so, (void)sc;/' \
  $ID 'IdentifyRules.Mirrored*' \
  "seed 003: Liebe's feature orientation (mirror images rejected)"
mutant magnitude-tiebreak sensors/identify/few_stars.cpp \
  's/ > chi2_max\) return false;/ > 1e300 * chi2_max) return false;/' \
  $ID 'MagnitudeTieBreak.*' \
  "seed 000: 2-3 star fields, catalog patterns kept only when the magnitude differences agree"
mutant magnitude-absent-star sensors/identify/few_stars.cpp \
  's/if \(!absent\) survivors.push_back\(c\);/if (!absent || true) survivors.push_back(c);/' \
  $ID 'MagnitudeTieBreak.*' \
  "2-3 star fields: a hypothesis predicting an unseen star brighter than a seen one is dropped"
mutant photometry-clipping sensors/identify/photometry.cpp \
  's/next\[i\] = std::abs\(r\[i\]\) <= lim;/next[i] = std::abs(r[i]) <= lim || true;/' \
  $ID 'Photometry.*' \
  "photometry: iteratively clipped least squares (outliers not followed)"
TR=st_test_tracking
mutant recursive-gate sensors/identify/recursive_id.cpp \
  's/if \(!\(d2 <= gate2\)\) continue;/(void)gate2;/' \
  $TR 'RecursiveIdRules.*' \
  "seed 002 step 5: the 3 sqrt(2) sigma gate (removed)"
mutant recursive-gate-sqrt2 sensors/identify/recursive_id.cpp \
  's/const double gate2 = opts_.gate_sigma \* opts_.gate_sigma;/const double gate2 = 2 * opts_.gate_sigma * opts_.gate_sigma;/' \
  $TR 'RecursiveIdRules.*' \
  "seed 002 step 5: the gate widened by sqrt(2) (3 sqrt(2) sigma counted twice)"
mutant recursive-gate-no-attitude-cov sensors/identify/recursive_id.cpp \
  's/const Mat2 S = windowed_\[k\]->cov_att_px \+ centroidCovariance/const Mat2 S = centroidCovariance/' \
  $TR 'RecursiveIdRules.*' \
  "seed 002 step 5: the attitude's share of the gate (H P H^T) left out"
mutant recursive-gate-floor-as-term sensors/identify/recursive_id.cpp \
  's/\+ centroidCovariance\(cen.cov_px\);/+ cen.cov_px + sigma_c_px_ * sigma_c_px_ * Mat2::Identity();/' \
  $TR 'RecursiveIdRules.*' \
  "seed 002 step 5: the centroid floor added as a third term (3 sqrt(3) sigma; issue 38 D3)"
mutant drop-saturated sensors/identify/recursive_id.cpp \
  's/if \(!opts_.drop_saturated\) return;/return;/' \
  $TR 'RecursiveIdRules.*' \
  "drop_saturated: saturated stars left out while min_stars others remain"
mutant drop-saturated-min-stars sensors/identify/recursive_id.cpp \
  's/if \(int\(unsaturated\) < opts_.min_stars \|\| /if (/' \
  $TR 'RecursiveIdRules.*' \
  "drop_saturated keeps saturated stars when fewer than min_stars others remain"
mutant blend-screen sensors/identify/recursive_id.cpp \
  's/if \(f \/ \(1 \+ f\) \* d.norm\(\) > max_pull\) return true;/if (f \/ (1 + f) * d.norm() > max_pull + 1e9) return true;/' \
  $TR 'BlendScreen.*' \
  "blend screen: a star an uncatalogued fainter neighbour pulls is not windowed"
mutant streaked-lis-remeasure sensors/tracking/star_tracker.cpp \
  's/^constexpr double kStreakedPx = 2.0;/constexpr double kStreakedPx = 2.0e9;/' \
  $TR 'LostInSpaceCovariance.*' \
  "streaked lost-in-space fixes re-measured by tracking (their covariance: 1.4x optimistic)"
mutant wide-prediction-lis sensors/tracking/star_tracker.cpp \
  's/    if \(half <= opts_.detect.max_window_half_px\) \{/    if (half <= opts_.detect.max_window_half_px + 1e9) {/' \
  "startracker st_test_app" 'ReplayGyroless.AcquiresAtFour*' \
  "a prediction wider than the largest window: lost-in-space (gyroless acquisition from two frames)"
mutant mrpt-allocation-throws sensors/mrpt/mrpt_allocation.cpp \
  's/^void\* aligned_malloc\(std::size_t size, std::size_t alignment\) \{/void* aligned_malloc_off(std::size_t size, std::size_t alignment) {/' \
  "startracker st_test_fuzz" 'FuzzRegressions.Matrix*' \
  "fuzz finding: an MRPT matrix of declared gigabytes is damage, not SIGSEGV (aligned_alloc's NULL)"
FU=st_test_fusion
mutant heads-disagreement fusion/fusion_loop.cpp \
  's/const bool agree = j.ok \&\& j.dof <= head_threshold_.maxDof\(\) \&\& j.chi2 <= head_threshold_\(j.dof\);/const bool agree = j.ok;/' \
  $FU 'FusionHeads.*' \
  "several heads: fixes that disagree beyond chi2(3 (N - 1)) are not merged"
DT=st_test_detect
mutant dark-frame sensors/detect/star_detector.cpp \
  's/cv::subtract\(grey, dark, s.dark_subtracted\);/s.dark_subtracted = grey;/' \
  $DT 'DetectRules.*' \
  "dark-frame subtraction before detection (full frame and tracking windows)"
mutant dark-median sensors/detect/dark_frame.cpp \
  's/const auto mid = v.begin\(\) \+ \(n - 1\) \/ 2;/const auto mid = v.begin() + (n - 1);/' \
  $DT 'DarkMedian.*' \
  "seed 004 sec. 4.1: the master dark is the per-pixel median (here: the maximum)"
TB=st_test_testbed
mutant near-field-correction sensors/testbed/display_geometry.cpp \
  's/return \(lever_arm_m \+ \*a \* b_B\)\.normalized\(\);  \/\/ seed 001 eq\. 54/return b_B;  \/\/ seed 001 eq. 54/' \
  $TB 'NearFieldSolver.*:DisplayGeometry.*' \
  "seed 001 eq. 54-56: the camera vectors corrected to the near-field vectors R_0 + alpha_i b_i"
mutant near-field-iteration sensors/testbed/near_field_solver.cpp \
  's/    q = r\.passes\.back\(\)\.q_ib;  \/\/ the estimate is the next prediction/    (void)0;  \/\/ the estimate is the next prediction/' \
  $TB 'NearFieldSolver.*:TestbedDrawSolve.*' \
  "seed 001 sec. IV.B: each update's estimate is the next update's prediction"
mutant dynamic-threshold sensors/detect/star_detector.cpp \
  's/k_ = std::max\(opts_.dynamic_min_sigma, k_ - opts_.dynamic_step_sigma\);/(void)0;/' \
  $DT 'DynamicThreshold.*' \
  "seed 004 sec. 8.2.3: a sparse frame lowers the next frame's threshold"
mutant streak-pieces sensors/detect/streaks.cpp \
  's/chainedLength\(stars, k, streakLength\(c\), u, 1.5 \* psf, 3.0 \* psf\)/chainedLength(stars, k, streakLength(c), u, -1.0, 3.0 * psf)/' \
  $DT 'StreakShapes.*' \
  "blind streak length: pieces of a broken streak joined (their own lengths set 5 px for 13 px)"
mutant diffuse-ranking sensors/detect/detect_frame.cpp \
  's/const uint32_t demoted = kDiffuse \| /const uint32_t demoted = 0u | /' \
  st_test_app 'SolveClutter.Sim*:SolveClutter.Real*' \
  "issue 15: lamps and a lit foreground's patches (flux over peak, wing and clipped pixels beyond a star's) rank after the stars"
mutant pyramid-vote sensors/identify/pyramid.cpp \
  's/const bool vote = ctx.n > 4;/const bool vote = ctx.n > 4000;/' \
  st_test_app 'SolveClutter.Sim*' \
  "issue 15: a triangle's catalog pyramids counted by confirming 4th stars, at most 20 verified per triangle (off: every confirmed pyramid verified as found)"
APP=startracker
mutant mc-star-count-lt3 app/montecarlo/exp_star_count.cpp \
  's/return x < 3; \}/return x <= 3; }/' \
  "$APP st_test_app" 'MontecarloTables.*' \
  "Monte Carlo star-count table: P(N<3)"
mutant mc-star-count-lt4 app/montecarlo/exp_star_count.cpp \
  's/return x < 4; \}/return x <= 4; }/' \
  "$APP st_test_app" 'MontecarloTables.*' \
  "Monte Carlo star-count table: P(N<4)"
mutant mc-fov-selection-lt3 app/montecarlo/exp_fov_selection.cpp \
  's/lt3 \+= v < 3;/lt3 += v <= 3;/' \
  "$APP st_test_app" 'MontecarloTables.*' \
  "Monte Carlo fov-selection table: P(N<3) (seed 002 eq. 14)"
mutant mc-fov-selection-threshold app/montecarlo/exp_fov_selection.cpp \
  's/if \(std::isnan\(need4\) \&\& P4 < kThreshold\)/if (std::isnan(need4) \&\& P4 <= 2 * kThreshold)/' \
  "$APP st_test_app" 'MontecarloTables.*' \
  "Monte Carlo fov-selection table: the smallest FOV with P(N<4) < 0.01"
mutant mc-field-stop app/montecarlo/sky.cpp \
  's/field_stop_rad > 0 \? std::min/field_stop_rad < 0 ? std::min/' \
  "$APP st_test_app" 'SeedTables.*' \
  "seed 003: the 30 deg opening angle as a circular field stop (ignored)"
mutant mc-heads-apart app/montecarlo/exp_fov_selection.cpp \
  's/if \(h == 0\) return Mat3::Identity\(\);/if (h >= 0) return Mat3::Identity();/' \
  "$APP st_test_app" 'SeedTables.*' \
  "seed 002 Fig. 11: two heads 90 deg apart (here: both along one boresight)"
mutant mc-required-mag app/montecarlo/exp_star_count.cpp \
  's/if \(lowest >= n_min\)/if (lowest > n_min)/' \
  "$APP st_test_app" 'SeedTables.*' \
  "seed 004 Table 5.1: the smallest limit whose minimum star count reaches N"
# Radiation hits (issue 34, sensors/detect/radiation_hits.hpp).
DT=st_test_detect
mutant hit-rule-detect sensors/detect/detect_frame.cpp \
  's/      flags \|= kRadiationHit;/      (void)kRadiationHit;/' \
  "$DT $ID" 'RadiationHits.*:InflightLis.*' \
  "issue 34: a blob bare along x, y or a diagonal against the frame's PSF is a radiation hit"
mutant hit-rule-window sensors/detect/detect_windows.cpp \
  's/  if \(opts.flag_hits \&\& !ws.streak \&\&/  if (false \&\& opts.flag_hits \&\& !ws.streak \&\&/' \
  "$DT" 'RadiationHits.*' \
  "issue 34: a tracking window refuses a hit at its peak"
mutant hit-ranked-last sensors/detect/detect_frame.cpp \
  's/return \(c.flags \& kRadiationHit\) \? 2 :/return (c.flags \& kRadiationHit) ? 0 :/' \
  "$DT" 'RadiationHits.*' \
  "issue 34: hits ranked after every star"
mutant hit-psf-cluster sensors/detect/radiation_hits.cpp \
  's/return std::abs\(std::log\(a.x \/ b.x\)\) < tol \&\& std::abs\(std::log\(a.y \/ b.y\)\) < tol;/return (void)a, (void)b, (void)tol, true;/' \
  "$DT $ID" 'RadiationHits.*:InflightLis.*' \
  "issue 34: the frame's PSF is the largest tight cluster of blob widths (not all blobs' median)"
mutant mc-psf-width app/montecarlo/exp_magnitude_error.cpp \
  's/s.psf_sigma_px = seed004PsfSigma\(kPsfWidthPx\);/s.psf_sigma_px = kPsfWidthPx \/ 2.3548200450309493;/' \
  "$APP st_test_app" 'SeedTables.*' \
  "seed 004 eq. 4.13: the PSF's sigma = psfWidth / 4 (read as the FWHM instead)"
mutant mc-defocus-psf-width app/montecarlo/exp_centroid_defocus.cpp \
  's/const double sigma = seed004PsfSigma\(c.psf_width\);/const double sigma = c.psf_width \/ 2.3548200450309493;/' \
  "$APP st_test_app" 'MontecarloCentroid.*' \
  "seed 004 eq. 4.13 (issue 38 D1): centroid-defocus's PSF sigma = psfWidth / 4 (read as the FWHM instead)"
mutant triad-anchor-first sensors/attitude/triad.cpp \
  's/      if \(obs\[k\].sigma < obs\[i1\].sigma\) i1 = k;/      if ((void)k, false) i1 = k;/' \
  st_test_attitude 'TriadRules.*' \
  "seed 001 TRIAD: the anchor is the most precise vector (issue 38 item 7; not the first listed)"
mutant triad-second-first sensors/attitude/triad.cpp \
  's/const double info = b1.cross\(obs\[k\].b\).squaredNorm\(\) \/ \(obs\[k\].sigma \* obs\[k\].sigma\);/const double info = 1.0 \/ (1.0 + double(k));/' \
  st_test_attitude 'TriadRules.*' \
  "seed 001 TRIAD: the second vector fixes the rotation about the anchor best (not the next listed)"
mutant pad-no-steps sensors/attitude/pad.cpp \
  's/constexpr int kMaxSteps = 30;/constexpr int kMaxSteps = 0;/' \
  st_test_attitude 'Pad.*:AllSolvers/WahbaSolverTest.*' \
  "seed 004 eq. 6.13/6.9: PAD's model-error steps (without them it is its TRIAD start)"
mutant pad-isotropic-only sensors/attitude/pad.cpp \
  's/        if \(o.cov.isZero\(0\)\) \{/        if (true) {/' \
  st_test_attitude 'Pad.*' \
  "seed 004 eq. 6.13: PAD weighs each star by its own R_i (anisotropic errors)"

# A mutant's expression: sed -E substitutions separated by @@ (code holds ';').
applySed() {  # expr file [-i]
  local args=() p
  while IFS= read -r p; do args+=(-e "$p"); done < <(printf '%s\n' "$1" | sed 's/@@/\n/g')
  if [[ "${3:-}" == -i ]]; then sed -E -i "${args[@]}" "$2"; else sed -E "${args[@]}" "$2"; fi
}

selected() {
  [[ ${#ONLY[@]} -eq 0 ]] && return 0
  local n
  for n in "${ONLY[@]}"; do [[ "$n" == "$1" ]] && return 0; done
  return 1
}

# ---- --check: every expression still changes its file --------------------------------------
if [[ $CHECK -eq 1 ]]; then
  bad=0
  for i in "${!NAMES[@]}"; do
    selected "${NAMES[$i]}" || continue
    f="$ROOT/${FILES[$i]}"
    if [[ ! -f "$f" ]]; then
      echo "${NAMES[$i]}: ${FILES[$i]} does not exist"; bad=1; continue
    fi
    if applySed "${EXPRS[$i]}" "$f" | cmp -s - "$f"; then
      echo "${NAMES[$i]}: the expression no longer matches ${FILES[$i]}"; bad=1
    else
      # Every ;-separated substitution must match on its own (a partial mutant is another one).
      while IFS= read -r p; do
        if applySed "$p" "$f" | cmp -s - "$f"; then
          echo "${NAMES[$i]}: part '$p' no longer matches ${FILES[$i]}"; bad=1
        fi
      done < <(printf '%s\n' "${EXPRS[$i]}" | sed 's/@@/\n/g')
    fi
  done
  [[ $bad -eq 0 ]] && echo "all ${#NAMES[@]} mutant expressions match"
  exit $bad
fi

# ---- the table's rows: "| `name` | rule | `file` | result | `commit` |" ---------------------
rowOf() {  # table name -> the row's line, or nothing
  grep -E "^\| \`$2\` \|" "$1" | head -1 || true
}
rowField() {  # line k -> the k-th cell (1-based), trimmed
  printf '%s\n' "$1" | awk -F' [|] ' -v k="$2" '{ v = $k; gsub(/^[|] |`| [|]$/, "", v); print v }'
}

# ---- --check-table: every row measured after the last change of the file it mutates ---------
if [[ -n "$CHECK_TABLE" ]]; then
  [[ -f "$CHECK_TABLE" ]] || { echo "mutants.sh: $CHECK_TABLE: no such table" >&2; exit 2; }
  bad=0
  for i in "${!NAMES[@]}"; do
    name="${NAMES[$i]}" file="${FILES[$i]}"
    row="$(rowOf "$CHECK_TABLE" "$name")"
    if [[ -z "$row" ]]; then echo "$name: no row in $CHECK_TABLE"; bad=1; continue; fi
    result="$(rowField "$row" 4)" at="$(rowField "$row" 5)"
    if [[ "$result" != KILLED* ]]; then echo "$name: $result"; bad=1; continue; fi
    if ! git -C "$ROOT" rev-parse -q --verify "$at^{commit}" >/dev/null; then
      echo "$name: the row names no commit ('$at')"; bad=1; continue
    fi
    last="$(git -C "$ROOT" log -1 --format=%h -- "$file")"
    if [[ -n "$last" ]] && ! git -C "$ROOT" merge-base --is-ancestor "$last" "$at"; then
      echo "$name: stale: $file changed at $last, after the row's commit $at"; bad=1
    fi
  done
  [[ $bad -eq 0 ]] && echo "all ${#NAMES[@]} rows of $CHECK_TABLE killed, none older than its file"
  exit $bad
fi

if [[ -n "$MD" ]] && ! git -C "$ROOT" diff --quiet HEAD; then
  echo "mutants.sh: --md needs a committed tree: each row records the commit it measured" >&2
  exit 2
fi

# ---- the scratch copy ------------------------------------------------------------------------
# The copy keeps the tree's layout (sources at the top, build/ inside) so that ccache, with
# base_dir=/work, sees the same relative paths as in the tree's own build and hits.
SCRATCH="${MUTANTS_DIR:-$ROOT/build-mutants}"
SRC="$SCRATCH" BLD="$SCRATCH/build"
mkdir -p "$SRC"
# The commit the table names: the tree as copied (not as it is when the table is written,
# when its own file is open and other work may have gone on).
commit="$(git -C "$ROOT" rev-parse --short HEAD)$(git -C "$ROOT" diff --quiet HEAD 2>/dev/null || echo ' (with uncommitted changes)')"
echo "copying the tree to $SRC"
(cd "$ROOT" && tar --exclude='./build*' --exclude='./.git' --exclude='./out' -cf - .) |
  (cd "$SRC" && tar -xf -)
# ccache when there is one (scripts/install-deps.sh does not install it: only this script
# gains, and a machine without it just builds the copy in full).
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$SRC" -B "$BLD" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
  -DST_SHARED_DATA_DIR="$ROOT/../shared/data" >/dev/null
JOBS="${MUTANTS_JOBS:-2}"

# The unmutated tests must pass, or a "kill" proves nothing.
declare -A BASE_OK=()
baseline() {  # target filter
  local key="$1|$2"
  [[ -n "${BASE_OK[$key]:-}" ]] && return 0
  cmake --build "$BLD" -j"$JOBS" --target $1 >"$BLD/mutant-build.log" 2>&1 ||
    { echo "baseline build of $1 failed (see $BLD/mutant-build.log)"; exit 1; }
  local exe; exe="$(testExe "$1")"
  if ! (cd "$BLD/tests" && "$exe" --gtest_filter="$2" >"$BLD/mutant-base.log" 2>&1); then
    echo "the unmutated tests $2 fail (see $BLD/mutant-base.log)"; exit 1
  fi
  BASE_OK[$key]=1
}
testExe() {  # the gtest executable among the targets
  local t
  for t in $1; do [[ $t == st_test_* ]] && { echo "$BLD/tests/$t"; return; }; done
}

ROWS=()
survived=0
for i in "${!NAMES[@]}"; do
  name="${NAMES[$i]}"
  selected "$name" || continue
  file="${FILES[$i]}" targets="${TARGETS[$i]}" filter="${FILTERS[$i]}"
  baseline "$targets" "$filter"
  cp "$SRC/$file" "$BLD/mutant.orig"
  applySed "${EXPRS[$i]}" "$SRC/$file" -i
  if cmp -s "$SRC/$file" "$BLD/mutant.orig"; then
    echo "$name: the expression does not match $file"; exit 1
  fi
  result=""
  if ! cmake --build "$BLD" -j"$JOBS" --target $targets >"$BLD/mutant-build.log" 2>&1; then
    cp "$BLD/mutant.orig" "$SRC/$file"
    echo "$name: the mutant does not compile (see $BLD/mutant-build.log)"
    # Rebuild unmutated: the next run's copy keeps the file's older mtime, and make would
    # keep an object of an earlier, compiled mutant.
    cmake --build "$BLD" -j"$JOBS" --target $targets >/dev/null 2>&1 || true
    exit 1
  fi
  exe="$(testExe "$targets")"
  (cd "$BLD/tests" && "$exe" --gtest_filter="$filter" >"$BLD/mutant-$name.log" 2>&1) || true
  killers="$(sed -n 's/^\[  FAILED  \] \([A-Za-z0-9_./]*\) (.*/\1/p' "$BLD/mutant-$name.log" | sort -u | paste -sd, -)"
  cp "$BLD/mutant.orig" "$SRC/$file"
  if [[ -n "$killers" ]]; then
    result="KILLED by ${killers//,/, }"
  else
    result="SURVIVED"
    survived=$((survived + 1))
  fi
  printf '%-32s %s\n' "$name" "$result"
  ROWS+=("| \`$name\` | ${RULES[$i]} | \`$file\` | $result | \`${commit%% *}\` |")
done
# Leave the scratch build unmutated (the next run starts from it).
for t in $(printf '%s\n' "${TARGETS[@]}" | tr ' ' '\n' | sort -u); do
  cmake --build "$BLD" -j"$JOBS" --target "$t" >"$BLD/mutant-build.log" 2>&1 || true
done

if [[ -n "$MD" ]]; then
  # Rows of this run replace theirs; the other mutants keep the row (and commit) of the run
  # that measured them; a mutant never run says so (--check-table refuses it).
  declare -A NEW=()
  for r in "${ROWS[@]}"; do NEW["$(rowField "$r" 1)"]="$r"; done
  FINAL=()
  survived=0
  for i in "${!NAMES[@]}"; do
    name="${NAMES[$i]}"
    if [[ -n "${NEW[$name]:-}" ]]; then r="${NEW[$name]}"
    elif [[ -f "$MD" && -n "$(rowOf "$MD" "$name")" ]]; then r="$(rowOf "$MD" "$name")"
    else r="| \`$name\` | ${RULES[$i]} | \`${FILES[$i]}\` | not run | - |"
    fi
    [[ "$(rowField "$r" 4)" == KILLED* ]] || survived=$((survived + 1))
    FINAL+=("$r")
  done
  {
    echo "# Mutants: does a test notice when a paper's rule is removed?"
    echo
    echo "Generated by \`scripts/mutants.sh --md docs/mutants.md [NAME...]\`, last on $(date -u +%Y-%m-%d)"
    echo "at commit \`${commit%% *}\`; each row names the commit it was measured at, and"
    echo "\`scripts/mutants.sh --check-table docs/mutants.md\` refuses a row older than the last"
    echo "change of the file it mutates (issue 38, D4)."
    echo "Each mutant is a sed expression in the script applied to a scratch copy of the tree;"
    echo "the test executable named there is rebuilt and the tests of the filter are run. A mutant"
    echo "is killed when at least one of them fails."
    echo
    echo "| mutant | rule removed or broken | file | result | commit |"
    echo "|---|---|---|---|---|"
    printf '%s\n' "${FINAL[@]}"
    echo
    echo "$survived of ${#FINAL[@]} mutants not killed (survived or not run)."
    cat <<'EOF'

## How the identification rules are seen without the verification's rescue

The shared verification accepts any pattern that leads to the right stars, so "never wrong"
says nothing about a paper's own rule. `tests/identify/test_identify_rules.cpp` therefore
makes each identifier propose ONE hypothesis (verification off, `max_verifications = 1`, no
retry) and reads that hypothesis's seed pairs exactly as the identifier built them: a Wahba
solver registered by the test records the pairs of the first solve of the search, which is
`verifySeeds()` solving the seeds. Rates with and without each rule (fixed seeds):

| rule | scenes | with the rule | rule removed |
|---|---|---|---|
| voting spike bound (spike put first) | 100 | 7 spike references | 100 |
| voting eq. 15 (unique companion) | 100 | 100 right | 59 |
| planar / spherical area and polar moment | 400 | 366 / 375 right | 4 / 6; one of the two alone: 330-348 |
| Liebe vertex angle | 100 | 99 right | 66 |
| Liebe image rim (scenes where it applies) | 100 | 0 features beyond the rim | 80 |
| n-vertex baselines BC, BD, CD (0.5 px noise) | 200 | 199 right | 0 |
| Pyramid 4th star (0.5 px noise) | 200 | 197 right | 59 |
| handedness on a mirrored sky (pyramid, planar, nvertex, liebe) | 50 each | 1, 0, 0, 0 mirror matches | 50, 39, 50 (shared test), 49 (Liebe's own) |

## Mutants left out, and why

- Voting's `n_x > n_smax` test alone is an equivalent mutant: a star's count is at most the
  number of non-empty slices, (n-1) - n_x, so with n_x > n_smax no star reaches the count
  f1 >= (n-1) - n_smax either. The spike rule is therefore mutated as a whole (both tests).
- n-vertex's "A in columns AB, AC and AD" skip is equivalent too (a star absent from a
  slice has no partners there); only a speed-up.
- n-vertex baseline CD alone: 199 -> 194 of 200 right at 0.5 px; the other five baselines
  nearly fix the quad, so no honest bound separates them.

## Found while writing the teeth

- The spike bound is weak in a catalog this dense: 7 of 100 first hypotheses still use the
  spike as reference (8 of 11 slices by chance), and the spike is named as a companion in
  15 of 100 (eq. 15 does not exclude a chance single occurrence). The verification's seed
  check removes both.
- Liebe's rim rule does not make the first hypothesis more often right (100/94/72 right with
  it, 99/94/84 without, at 0.1/0.3/0.5 px), because the catalog side registers every pair
  among four neighbours and so already survives a missing neighbour.
- The tracking windows (`StarDetector::centroidWindows`) ignored `DetectorOptions::dark_frame`
  (only full-frame detection subtracted it); fixed since, with
  `DetectRules.WindowsSubtractTheDarkFrameToo`.
EOF
  } >"$MD"
  echo "wrote $MD"
fi
[[ $survived -eq 0 ]]
