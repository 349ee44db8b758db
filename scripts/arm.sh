#!/usr/bin/env bash
# The aarch64 stage of scripts/test.sh (docs/embedding-arm.md): cross-compiles
# massid_core and massid_tests for aarch64 (Debian's g++-aarch64-linux-gnu)
# and runs the tests under qemu-user with ctest. Safe to run repeatedly; needs
# root (or sudo) for apt-get.
#
#   ARM_DIR            where it all goes: debs/, sysroot/, build/   (default build/aarch64)
#   ARM_CTEST_EXCLUDE  ctest -E regex (default: the tests that take more than 2 s each under
#                      qemu, step 4; "" runs them all)
#
# The arm64 libraries come from Debian's arm64 packages, fetched with
# `apt-get download` and unpacked with `dpkg -x` into ARM_DIR/sysroot, never
# installed: their -dev packages are not Multi-Arch: same, and installing the
# arm64 ones would remove the amd64 ones the normal build needs. The sysroot is
# made once (ARM_DIR/sysroot/.complete holds the package list it was made from).
set -euo pipefail
cd "$(dirname "$0")/.."
ARM=${ARM_DIR:-build/aarch64}
JOBS=$(nproc)
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO=sudo

# 1. The cross compiler, qemu-user and ccache (apt-get only for what is missing).
missing=()
for p in g++-aarch64-linux-gnu qemu-user ccache; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# 2. The sysroot: what massid_core and massid_tests link, and what those
#    libraries need in turn (apt-cache depends --recurse of the -dev packages,
#    less the C and C++ runtimes, which the cross compiler has in
#    /usr/aarch64-linux-gnu, and less the BLAS alternatives but the reference
#    one and ATLAS, which libceres.so links).
pkgs=(
  liburdfdom-dev liburdfdom-model3.0 liburdfdom-sensor3.0 liburdfdom-world3.0
  liburdfdom-model-state3.0 libconsole-bridge-dev libconsole-bridge1.0 libtinyxml-dev
  libtinyxml2.6.2v5 libtinyxml2-dev libtinyxml2-9 libfmt-dev libfmt9
  libceres-dev libceres3 libgoogle-glog-dev libgoogle-glog0v6 libgflags-dev libgflags2.2
  libsuitesparse-dev libsuitesparseconfig5 libamd2 libbtf1 libcamd2 libccolamd2 libcholmod3
  libcolamd2 libcxsparse3 libklu1 libldl2 libmetis5 libmongoose2 librbio2 libsliplu1 libspqr2
  libumfpack5 libgmp10 libmpfr6 libblas3 libblas-dev liblapack3 liblapack-dev libgfortran5
  libatlas3-base libatlas-base-dev libgtest-dev
)
# Architecture-independent (headers and CMake files), so that every package
# is found in the one sysroot.
pkgs_all=(libeigen3-dev liburdfdom-headers-dev nlohmann-json3-dev libfast-float-dev libcli11-dev)
SYSROOT=$ARM/sysroot
SYSROOT_ABS=$(realpath -m "$SYSROOT")
recipe="$SYSROOT_ABS: ${pkgs[*]} ${pkgs_all[*]}"
if [ "$(cat "$SYSROOT/.complete" 2>/dev/null)" != "$recipe" ]; then
  echo "Making the arm64 sysroot $SYSROOT"
  dpkg --print-foreign-architectures | grep -qx arm64 || $SUDO dpkg --add-architecture arm64
  # (as root, like the download below: where apt's _apt user cannot run gpgv,
  # the arm64 indexes were silently not fetched)
  apt-cache show libceres-dev:arm64 >/dev/null 2>&1 || $SUDO apt-get update -qq -o APT::Sandbox::User=root
  rm -rf "$ARM/debs" "$SYSROOT"
  mkdir -p "$ARM/debs" "$SYSROOT"
  # -o APT::Sandbox::User=root: _apt cannot write into this tree (a harmless warning otherwise).
  (cd "$ARM/debs" && apt-get download -qq -o APT::Sandbox::User=root "${pkgs[@]/%/:arm64}" \
    "${pkgs_all[@]}")
  for deb in "$ARM"/debs/*.deb; do dpkg -x "$deb" "$SYSROOT"; done
  lib=$SYSROOT/usr/lib/aarch64-linux-gnu
  # The links update-alternatives makes when the packages are installed.
  for so in blas/libblas.so.3 blas/libblas.so lapack/liblapack.so.3 lapack/liblapack.so; do
    ln -sf "$so" "$lib/${so#*/}"
  done
  # The packages' CMake files name some files by absolute path (/usr/include,
  # /usr/lib/aarch64-linux-gnu/libtinyxml.so, ...): point those into the sysroot.
  find "$SYSROOT" -name '*.cmake' -exec sed -i -E "s#([\"; ])/usr([/\"])#\1$SYSROOT_ABS/usr\2#g" {} +
  echo "$recipe" >"$SYSROOT/.complete"
fi

# 3. massid_core, massid_tests, massid_tracker_tests and the C interface (massid_c) for aarch64: -O2 without debug information
#    (compile time), a unity build as in scripts/test.sh, warnings as errors, without the emulator and the CLI
#    (MuJoCo), Python, benchmarks and fuzzers; ccache as in the normal build.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
cmake -S . -B "$ARM/build" --toolchain "$PWD/cmake/aarch64-linux-gnu.cmake" \
  -DMASSID_ARM_SYSROOT="$SYSROOT_ABS" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DCMAKE_UNITY_BUILD=ON \
  -DMASSID_WERROR=ON -DMASSID_EMULATOR=OFF -DMASSID_MUJOCO_TESTS=OFF -DMASSID_BENCH=OFF \
  -DMASSID_PYTHON=OFF -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
cmake --build "$ARM/build" -j "$JOBS" --target massid_tests massid_tracker_tests massid_c

# 4. The tests under qemu-aarch64 (ctest runs them through the toolchain
#    file's CMAKE_CROSSCOMPILING_EMULATOR), but for those that took more than
#    2 s each under emulation (a full run: 21 minutes, of which these 54 tests
#    are 20): identifications of long logs, Monte-Carlo seeds, design
#    searches, volume tests, and one rank count of every example's motion
#    basis. What stays (about 300 tests) includes every predictor, regressor,
#    kinematics, model and argument test, the predictors' 1-ulp reference
#    (PredictorReference.*) and smaller identifications through the same code.
slow_under_qemu='Delay.ALagBeyondTheScanIsNamed|Tracker.StandardisedErrorsOverFiftySeeds.*|Delay.OneMillisecondLagIsFoundAndTheFitIsAsGoodAsWithoutLag|Design.DOptimalityMaximisesTheLogDeterminant|Design.HeldJointsNarrowedRangesAndMinimumHeight|Design.Ur5DefaultsKeepTheArmAboveItsMountingPlateAndLevelPoses|Examples/EstimationTest.StandardDeviationsMatchTheErrorsOver200Seeds/.*|Excitation.DOptimalityRaisesTheLogDeterminant|Excitation.EveryWrittenSampleWithinTheLimitsAndAtRestAtBothEnds|Excitation.OptimisedConditionNumberThreeTimesBetterThanRandom|Excitation.PredictedStdMatchTheSpreadOverHundredNoiseSeeds|ManyArms.StandardDeviationsAreHonestWhenUnknownsApproachTheEquations|MotionAccumulator.AgreesWithIdentifyOnEveryExample|MotionBaseParameters.CountsAgreeWithAnIndependentRank|MotionCsvTest.BlockColumnRestartsTheFilter|MotionCsvTest.ErrorsAreThoseOfReadMotionSamples|MotionCsvTest.IdentifyMotionFileIsTheInMemoryPath|MotionCsvTest.LargestResidualWithoutASecondPass|MotionCsvTest.SensorMidChainWithMixedColumns|MotionCsvTest.ThreadCountDoesNotChangeTheResult|MotionCsvTest.VelocitiesDerivedInTheStreamAgreeWithInMemory|MotionCsvTest.VelocitiesGivenAgreeWithInMemory|MotionCsvTest.WhatTheHeadSuggestsIsCheckedAgainstTheWholeFile|MotionCsvTest.WristSensorWithTheArmJointsAbove|MotionCsvTest.WristSensorPoseInMemoryAsInTheStream|MotionFilterTest.DefaultDecimationDecorrelatesNoise|MotionIdentify.BaseParametersWithinFourStdAndPredictionWithinOnePercent|MotionIdentify.DerivativesFromPositionsStayWithinFourStd|MotionIdentify.ReportedStdMatchTheSpreadOverSeeds|MotionIdentify.TiltedGravityDeterminesTheTotalMassWithOffsets|MotionIdentify.ToolOnAWristSensorFromTheArmJoints|NumericalRange.AMillionSamples|NumericalRange.NoisyRecoveryIsAsTheStdPredictAtEveryScale|Physical.ImplausibleEstimateGivesRealBodiesAndSaysHowFar|Physical.ParamsFileAndRecordRoundTrip|Physical.SummaryOfAnotherModelIsAnInputError|Physical.TheDataOverridesThePriorWhereItSees|Physical.WellExcitedLogIsReproducedWithinItsStdByConsistentBodies|Physical.WhatTheDataCannotSeeKeepsTheUrdfsValues|PlainDecimal.SameDoubleAsFastFloat|PumaDesign.AnyTiltUpTo25DegreesReaches2Point5|PumaDesign.FourTiltGroupsKeepTheTargetWithThreeTiltChanges|PumaDesign.OffsetsNeedAThirdGravityDirection|PumaDesign.PapersConstraintsBeatThePapersTenPointEight|PumaDesign.PredictedStandardDeviationsMatchIdentifiedErrors|PumaDesign.SameSeedSamePlanOtherSeedOtherPlan|RestWindows.FoundWhereTheRobotRestedAndTheFitIsUnbiased|RestWindows.IdentifyFileUsesTheWindowsOfAContinuousCsv|SetupChecks.HeadOfABigFileIsReadInPiecesWithTheFilesLines|StreamingTest.HundredThousandRowCsvRoundTrip|StreamingTest.RandomLogOfTenThousandRowsAgreesWithDense|StreamingTest.ThreadCountDoesNotChangeTheResult|Delay.PredictAndCompensateApplyTheIdentifiedDelay|MotionIdentify.NegatedWrenchInMotionIsRefusedByTheFittedTotalMass|MotionUncertainty.PositionsOnlyStdMatchTheErrorsOverFiftySeeds|MotionUncertainty.DerivativeColumnsStdMatchTheErrorsOverFiftySeeds|MotionUncertainty.MovingPlatformStdMatchTheErrorsOverFiftySeeds'
exclude=${ARM_CTEST_EXCLUDE-^(${slow_under_qemu})$}
ctest --test-dir "$ARM/build" --output-on-failure -j "$JOBS" ${exclude:+-E "$exclude"}
