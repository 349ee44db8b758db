#!/usr/bin/env bash
# Installs what is missing, builds massid with warnings as errors and runs every
# test; then builds everything again with clang under AddressSanitizer and
# UndefinedBehaviorSanitizer, runs the library's suites there (stage 6 says
# which), and runs each libFuzzer target for a bounded time; and cross-compiles
# the library and its tests for aarch64 and runs them under qemu-user
# (scripts/arm.sh). Any test failure, sanitizer report or fuzzer finding fails
# the script.
#
#   BUILD_DIR      the normal build tree             (default build/test)
#   SANITIZE_DIR   the ASan+UBSan + libFuzzer tree   (default build/sanitize)
#   FUZZ_SECONDS   run time of each fuzz target, s   (default 30; 0 skips fuzzing)
#   SANITIZE_CTEST_EXCLUDE  ctest -E regex for the sanitizer stage (default: the volume and Monte-Carlo tests)
#   ARM            1 runs the aarch64 stage (default), 0 skips it
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD_DIR:-build/test}
SANITIZE=${SANITIZE_DIR:-build/sanitize}
FUZZ_SECONDS=${FUZZ_SECONDS:-30}
JOBS=$(nproc)
ARM=${ARM:-1}

# Each stage prints its wall time when it ends, and all of them at the end.
TIMES=()
stage_name=""
stage_start=$SECONDS
stage() {
  if [ -n "$stage_name" ]; then
    TIMES+=("$(printf '%5d s  %s' $((SECONDS - stage_start)) "$stage_name")")
    echo "== $stage_name: $((SECONDS - stage_start)) s"
  fi
  stage_name=$1
  stage_start=$SECONDS
  [ -z "$stage_name" ] || echo "== $stage_name"
}

# 1. Debian packages (apt-get only for what is missing).
stage "dependencies"
scripts/deps.sh

# 2. The normal build, the Python package included: RelWithDebInfo, warnings as errors; line tables only
#    (-g1) rather than full debug information, which cuts the compile time by a third
#    of the Eigen-heavy files. A unity build (CMAKE_UNITY_BUILD: eight .cpp
#    files compiled as one) parses Eigen, GoogleTest and nlohmann once per
#    eight files instead of once per file: about half the CPU time, a third less wall time (CI:
#    2 cores, 40 minutes for the whole script; docs/build.md).
stage "build ($BUILD)"
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMASSID_WERROR=ON -DCMAKE_UNITY_BUILD=ON \
  -DMASSID_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" >/dev/null
cmake --build "$BUILD" -j "$JOBS"

# 3. Every test: GoogleTest, and pytest on the Python package (tests/python:
#    the module against the CLI and independent sums, the HTML report, the
#    report in headless Chromium, `cmake --install` of the package).
stage "tests ($BUILD)"
ctest --test-dir "$BUILD" --output-on-failure -j "$JOBS"

# 4. The library and its tests cross-compiled for aarch64 and run under
#    qemu-user (scripts/arm.sh, docs/embedding-arm.md): the predictors there
#    within 1 ulp of x86-64's (tests/data/predictor_reference.txt).
if [ "$ARM" = 1 ]; then
  stage "aarch64 build and tests under qemu"
  scripts/arm.sh
fi

# 5. Everything again with clang, ASan + UBSan (-O1, assertions on, UB aborts;
#    line tables for the sanitizers' stack traces),
#    plus the fuzz targets (MASSID_FUZZ also adds libFuzzer's coverage
#    instrumentation). Without the benchmarks; without massid_alloc_tests,
#    which interposes malloc (tests/CMakeLists.txt).
stage "sanitizer build ($SANITIZE)"
cmake -S . -B "$SANITIZE" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DCMAKE_UNITY_BUILD=ON \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DMASSID_FUZZ=ON -DMASSID_BENCH=OFF >/dev/null
cmake --build "$SANITIZE" -j "$JOBS"

# 6. The library's suites under the sanitizers (leaks included: LeakSanitizer),
#    and the CLI's basic suites (Cli, CliChecks, CliRobust, CliCompensate): the
#    CLI is a thin printer of the library, and its end-to-end suites (design,
#    emulate, motion, physical, report, set-up mistakes: each test runs whole
#    identifications in several processes) were most of this stage's 16
#    minutes (CI: 2 cores, 40 minutes for the script); they run in the normal
#    build above. Also left to the normal build: volume tests that
#    take minutes under ASan (a 10^5-row CSV round trip, an exhaustive
#    D-optimal design search, three 30 s / 1 kHz motion logs per robot, 100
#    noise seeds of motion identification, two delay scans of 50 fits each),
#    and the tests that took more than 20 s each under ASan whose code a
#    smaller test of the same suite runs too (a 10^6-sample range scan, the
#    UR5 design defaults, two more design searches and an excitation
#    optimisation, motion CSVs compared whole, a Monte-Carlo of 100 noise seeds):
#    together half of this stage's 8 minutes. SANITIZE_CTEST_EXCLUDE="" runs them all.
stage "tests under ASan+UBSan ($SANITIZE)"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:check_initialization_order=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
volume='StreamingTest.HundredThousandRowCsvRoundTrip|Design.DOptimalityMaximisesTheLogDeterminant|MotionIdentify.BaseParametersWithinFourStdAndPredictionWithinOnePercent|MotionIdentify.ReportedStdMatchTheSpreadOverSeeds|MotionIdentify.DerivativesFromPositionsStayWithinFourStd|Delay.OneMillisecondLagIsFoundAndTheFitIsAsGoodAsWithoutLag|Excitation.PredictedStdMatchTheSpreadOverHundredNoiseSeeds|Excitation.OptimisedConditionNumberThreeTimesBetterThanRandom'
slow_under_asan='NumericalRange.AMillionSamples|Tracker.StandardisedErrorsOverFiftySeeds.*|Design.Ur5DefaultsKeepTheArmAboveItsMountingPlateAndLevelPoses|PumaDesign.FourTiltGroupsKeepTheTargetWithThreeTiltChanges|PumaDesign.AnyTiltUpTo25DegreesReaches2Point5|Excitation.DOptimalityRaisesTheLogDeterminant|MotionCsvTest.ErrorsAreThoseOfReadMotionSamples|MotionCsvTest.VelocitiesDerivedInTheStreamAgreeWithInMemory|MotionCsvTest.VelocitiesGivenAgreeWithInMemory|MotionAccumulator.AgreesWithIdentifyOnEveryExample|ManyArms.StandardDeviationsAreHonestWhenUnknownsApproachTheEquations|Delay.PredictAndCompensateApplyTheIdentifiedDelay|MotionIdentify.NegatedWrenchInMotionIsRefusedByTheFittedTotalMass|MotionUncertainty.PositionsOnlyStdMatchTheErrorsOverFiftySeeds|MotionUncertainty.DerivativeColumnsStdMatchTheErrorsOverFiftySeeds|MotionUncertainty.MovingPlatformStdMatchTheErrorsOverFiftySeeds'
cli_end_to_end='(CliDesign|CliDeterminism|CliEmulate|CliEmulateAsBuilt|CliMotion|CliPhysical|CliUrdfOut|CliReport|SetupMistakes|CliWrist|CliTracker|CliPose)\..*'
exclude=${SANITIZE_CTEST_EXCLUDE-^(${volume}|${slow_under_asan}|${cli_end_to_end})$}
ctest --test-dir "$SANITIZE" --output-on-failure -j "$JOBS" ${exclude:+-E "$exclude"}

# 7. Each fuzz target on its seed corpus (fuzz/corpus/NAME) for FUZZ_SECONDS,
#    all three at once; a crash, sanitizer report, leak, hang (-timeout) or
#    runaway memory (-rss_limit_mb) fails. New inputs go to a scratch corpus,
#    the repo's seeds are only read; a finding is saved under
#    $SANITIZE/fuzz/findings/ to replay with `$SANITIZE/fuzz/fuzz_NAME FILE`.
if [ "$FUZZ_SECONDS" -gt 0 ]; then
  stage "fuzzing, ${FUZZ_SECONDS} s per target"
  findings="$SANITIZE/fuzz/findings"
  rm -rf "$SANITIZE/fuzz/work"
  mkdir -p "$findings"
  pids=()
  for name in csv params urdf; do
    mkdir -p "$SANITIZE/fuzz/work/$name"
    "$SANITIZE/fuzz/fuzz_$name" "$SANITIZE/fuzz/work/$name" "fuzz/corpus/$name" \
      -max_total_time="$FUZZ_SECONDS" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$findings/$name-" >"$SANITIZE/fuzz/$name.log" 2>&1 &
    pids+=($!)
  done
  failed=()
  for i in 0 1 2; do
    name=$(echo csv params urdf | cut -d' ' -f$((i + 1)))
    if wait "${pids[$i]}"; then
      echo "fuzz_$name: $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' \
        "$SANITIZE/fuzz/$name.log" | grep -o '[0-9]*$') runs, no finding"
    else
      failed+=("$name")
      echo "fuzz_$name FAILED; the end of its log ($SANITIZE/fuzz/$name.log):"
      grep -v '^#[0-9]' "$SANITIZE/fuzz/$name.log" | tail -40
    fi
  done
  [ ${#failed[@]} -eq 0 ] || { echo "fuzz targets with findings: ${failed[*]}"; exit 1; }
fi

stage ""
echo "== wall time of each stage:"
printf '%s\n' "${TIMES[@]}"
echo "== total: ${SECONDS} s"
