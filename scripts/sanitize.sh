#!/usr/bin/env bash
# The tests under AddressSanitizer + UndefinedBehaviorSanitizer (build/asan: -O1, line tables).
# Not part of scripts/test.sh: the whole suite sanitized took about half of an 80-minute run of
# it on 2 cores, past CI's budget; there the parsers run sanitized through their fuzz targets.
# Run it before a release, or on the folders a change touches:
#
#   scripts/sanitize.sh [FOLDERS]   e.g. "map;io" (the tests in those folders of tests/, built
#                                   with only the components they link); default: every test
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"
VDTNAV_TEST_ONLY="${1:-}" scripts/setup.sh asan vdtnav_tests
# Under the sanitizers the long simulations run 10-20x slower: the Monte Carlo calibrations, the
# kidnapped-robot drives, the occupancy mapping of a whole run, the exhaustive global search, the
# 3D teleports, the maps rebuilt per Monte Carlo trial, the drive through rooms the map lacks and
# the real logs through the CLI (lost detection) are left to the Release run; their code paths
# run here through the shorter tests of the same classes.
skip='BuildOccupancyMap\.ReproducesTheSimulatorsFloorPlan|Covariance\..*MonteCarlo'
skip+='|Kidnapped\.|VdtLocalizer3\.ATeleport|RecoveringLocalizer3\.ATeleported'
skip+='|GlobalLocalization\.BestLeafIsTheExhaustive|GlobalLocalizer3\.TheBestLeafIsTheBruteForce'
skip+='|RecoveringLocalizer\.APlaceTheMapLacks|CliRealLogs\.|\.MapsRebuiltFromNoisyScans'
# ... and the longest brute-force comparisons (30-50 s each there), whose classes run through
# their other tests: the attitude grid of the 3D multi-start, the map-noise floor of the 3D
# covariance, the optimizer's map-uncertainty Monte Carlo, the sparse map against the dense one
# everywhere in the band, and the thread-count comparisons of the multi-start and the global
# search (each solve or search run 5-8 times over).
skip+='|MultiStart\.TheAttitudeGrid|VdtOptimizer3Covariance\.MapNoiseFloor'
skip+='|MapUncertainty\.OptimizerCovarianceCovers'
skip+='|SparseVdtMap\.(AgreesWithTheDenseMapInsideTheBand|ToleranceIsTight)'
skip+='|(MultiStart|GlobalLocalization)\.TheSameResultForAnyThreadCount'
# The ROS node on a live graph plays a bag at its rate and ten times faster: under the sanitizers
# it cannot keep that pace, which is what those tests check; LiveLocalizer, its core, runs here.
skip+='|LocalizerNode\.'
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -E "$skip"
