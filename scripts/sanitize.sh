#!/usr/bin/env bash
# The sanitizer and fuzz jobs (scripts/test.sh runs this after the release suite; so does CI).
#   1. builds dynid, the unit tests and the fuzz targets with clang, AddressSanitizer and
#      UndefinedBehaviorSanitizer in build-asan/ (-O1 with dynid's assertions on; Eigen's own index
#      checks off: AddressSanitizer catches the out-of-bounds accesses they would, and with them
#      a search's test ran 160x slower than in the release build; the tests' own code at -O0,
#      cmake/DynidHelpers.cmake). The long end-to-end test
#      programs are not built there (DYNID_SANITIZER_SKIPPED_TESTS in tests/CMakeLists.txt);
#   2. runs the unit tests and the whole bad-input suite there, except the long tests listed in
#      SKIP below (they run in the release suite);
#   3. fuzzes each target for DYNID_FUZZ_SECONDS (default 10) from its seed corpus.
# Any sanitizer report fails the test that triggered it (halt_on_error, -fno-sanitize-recover).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${DYNID_ASAN_BUILD:-build-asan}
seconds=${DYNID_FUZZ_SECONDS:-10}
jobs=$(nproc)
generator=()  # Ninja for a new directory (as scripts/test.sh)
if [ ! -f "$build/CMakeCache.txt" ] || grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$build/CMakeCache.txt"; then
  generator=(-G Ninja)
fi
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="-O1 -g1 -DEIGEN_NO_DEBUG" -DDYNID_SANITIZE=ON -DDYNID_FUZZ=ON -DDYNID_FUZZ_SECONDS="$seconds" \
  -DDYNID_BUILD_TESTS=ON -DDYNID_BUILD_BENCH=OFF -DCMAKE_UNITY_BUILD=ON  # as scripts/test.sh
start=$SECONDS
cmake --build "$build" -j"$jobs"
echo "sanitize.sh: the sanitizer build took $((SECONDS - start)) s" >&2
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# End-to-end runs in programs that are otherwise kept, and the heaviest numerical checks (a
# gradient check of every segment cost, a 12-fit coverage statistic, a 100000-row file, two
# refinements compared bit for bit, a memoised search and refinement, every command under hostile
# names, a search resumed from its checkpoint, 40 payload fits for their coverage, 120 audited
# identifications and the hac audit's 110, a simulated loaded/unloaded pair end to end, band
# coverage over 20000 samples and through the CLI, dense reference
# solutions built in the test's own code (-O0 here), estimates and designs repeated for every
# thread count, refinements repeated for every thread count (9 min alone under the sanitizers on
# a 2-core Zen 3), a Ctrl-C during a long read, three 100000-row streams under a memory cap, the
# combined estimator's trade and noise floor, two simulated logs prepared and identified with their
# filter reproduced, a 203,000-sample log summarized from its file and from memory (78 s), the
# floating base's heaviest statistics (300 states within friction cones for every set, 200 draws
# of each state refused, a humanoid's soles (a thousand draws), eight seeds' z, both example
# robots' counts beside their virtual chains, a loaded/unloaded pair, a foot outline's soles (29 s)), excite's unset starts run
# three times (70 s), and three end-to-end CLI runs: the combined estimator, the Panda simulated
# and tracked, and the front (180 s, 54 s, 49 s); a front of two combined points and every
# method's estimate read back, the combined one's included (77 s, 75 s)): 15 s to minutes each
# under the sanitizers
# (20-50x the release suite; the cone solver, the pair, the counts and the combined estimator still
# run under them in their smaller tests). The summary's head still runs under them in the other
# summarize tests (logs read once). excite --stands end to end (an ANYmal design, its GC Jacobian
# and the stand choice: over 13 CPU minutes under them, 8 s in release); the choice itself runs
# under them in floating_runs' StandTilts tests (19 s together). The standing sway's design searches
# (ANYmal's, its repeat from the same seed and Romeo's soles: 37, 24 and 54 s under them); its
# refusals, motions and CLI run end to end under them. Nine more that repeat what smaller tests run
# under them (2026-12-04, 195 s of the sanitizer suite's test time): results compared across
# thread counts and chunks (a suspended robot's GC term, the covariance's replay, a CSV's rows),
# the combined cost's gradient by central differences, the floating combined estimator stopped
# before its first step (it runs end to end in Cli.IdentifyAFloatingBaseByTheCombinedEstimator),
# merged summaries (Cli.SummariesGiveTheEstimateOfTheLogsTogether merges them), and a push at
# rest in the monitor and through the CLI (StateResidual's tests, the monitor's run at rest and
# the CLI's other monitor tests still run under them), and a carried recording's four
# identifications (39 s; Cli.PrepareAFloatingRecordingThenIdentifyIt identifies one as carried).
SKIP='GradientCheckerOnEverySegmentCost|ALogIsSummarizedAsItsSamplesInMemoryShortOrLong|PandaLogAsARos1Bag|RefineFromIsTheRefinementOfAnyPoint|ReportedSigmaCoversTheErrors|row_malformed_deep_in_a_long_file|PandaExampleRunsAndBeatsThePublishedFit|RefineFromASearchAndFromAnEstimate|APumaDesignBeatsTheDefaultSinusoid|TheRelativeSdCriterionLowers|TorqueAndFloorLimitsAreKept|TheFirstOrderGcCriterionTracks|ExciteIsTheSameForAnyThreadCount|ExciteWritesTheDesignItsTrajectory|SimulateTracksADesignedExcitation|BatchTrainsOnADesignedTrajectory|RunnerMemoisesSearchesAndRefinesTheirResult|HostileNamesInARobotFileItsPathAndTmpdir|SearchWritesHistoryAndResumesFromACheckpoint|IntervalsCoverTheTruthAtTheirLevel|FlagsAChangedFrictionTermAndLittleElse|HacHoldsOnFilteredResidualsAndModelError|AttachedBodyPairRecoversIt|CoversNinetyFivePercentOfDataWithTheTrainingNoise|NoiseFreeDataGiveTheTrueProjection|TheSameSeedGivesTheSameDesignWithAnyThreadCount|IdentifyGivesTheSameEstimateOnAnyThreadCount|KeepsEveryStrideThSampleWhateverTheChunks|PredictDrawsTheBandAndWarnsWhenItDoesNotCoverTheData|OlsAndWlsEqualTheDenseSolution|IndependenceIsTheUnexplainedShareOfEachColumn|CtrlCDuringALongReadLeavesNothing|rows_huge_streamed_under_memory_cap|TradesTorqueFitForMotionAndStaysConsistent|DoesNotFitTheGcErrorBelowItsNoiseFloor|TheNoiseFloorIsTheGcErrorTheTorqueNoiseCauses|EveryLongCommandStopsSoonAfterCtrlC|SearchAndExciteHoldTheirTimeBudgets|RefinementsGiveTheSameBitsForAnyThreadCount|ThroughPreparesLowPassTheFrictionAndTheIntervalsHold|IdentifyReproducesPreparesTorqueFilter|APushWhereTheModelIsGoodIsFoundBelowTheReversalsError|OnAFilteredLogItsErrorIsIdentifysHeldOutError|IdentifyExciteSearchAndPayloadRerunToTheSameDocuments|RefineReadsEitherSearchVersionAndBothEmbedTheRobot|RefineRefusesAnotherRobotThanTheStartWasMadeOn|EveryFootPushesWithinItsConeAndTheSetsStillRecover|AreRefusedWhereNoContactStandsOnTheGround|GeneralizedLeastSquaresIntervalsAreCalibrated|ExampleRobotsCountsEqualTheVirtualChains|FromALoadedUnloadedPairItNeedsNoRobotParameters|UnsetStartsAreEightOrSixteenForAPayloadMotion|ASolesCentreOfPressureStaysInIt|CombinedWithoutTheGcFloorFitsBelowIt|SimulatedPandaTracksWithoutChatterAndIdentifiesToItsNoiseFloor|IdentifyFrontTakesThePointTheHeldOutDataChoose|EveryPointIsConsistentAndTradesTorqueFitForMotion|EveryMethodsEstimateReadsBack|ASolePolygonOffTheFrameHoldsItsCentreOfPressure|TheNoiseFloorIsTheTrueModelsErrorOnNoisyInputs|SaysHowMuchCloserTheEstimateRollsOutThanTheModelRead|FlagsAloneAreRolledOutHeld|ExciteChoosesStandTiltsThatSimulateUses|EverySetRollsOutAtItsFloorAndKeepsItsFit|ACombinedEstimateTurnsAWrongTrunkBackIntoTheRobots|KeepsAHumanoidsCentresOfPressureInItsSoles|DeterminesWhatASwayCanWithinItsBoundsAndTheCones|TheSameSeedGivesTheSameDesign|AStopKeepsPcsEstimate|Suspended.TheSameForAnyThreadCount|TheReplayAndTheObservationGiveTheSameCovarianceForAnyThreadsAndChunks|RowsFormattedOnThreadsAreTheRowsInOrder|GradientMatchesCentralDifferencesOfTheCost|MergedSummariesGiveTheConcatenatedLogsEstimate|AtRestAPushIsJudgedByTheNoiseAtRestNotByTheMovingResidual|SaysHowARestingArmIsJudgedAndKeepsItsThresholdsAtRest|ACarriedRecordingIsIdentifiedAsCarried'
start=$SECONDS
ctest --test-dir "$build" --output-on-failure -j"$jobs" -LE fuzz -E "$SKIP"
echo "sanitize.sh: the sanitizer suite took $((SECONDS - start)) s" >&2
ctest --test-dir "$build" --output-on-failure -j"$jobs" -L fuzz
