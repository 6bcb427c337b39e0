#!/usr/bin/env bash
# Fuzz StripWeave's input parsers (issue 23).
#   tests/fuzz/run.sh [SECONDS [TARGET...]]   default 60 s per target, targets: mesh design
#   FUZZ_TIMEOUT=S   seconds one input may take before it counts as a hang (default 60)
#   FUZZ_OUT=DIR     work folder (default build/fuzz): binary, growing corpus, findings
#   FUZZ_KEEP_GOING=1  mesh: go on past a timeout (libFuzzer -fork=1 -ignore_timeouts=1), for long
#                    runs at a low priority, where a busy machine can starve one input past the
#                    timeout (wall clock); re-run each timeout-* alone to tell a real hang
# Targets:
#   mesh    libFuzzer (clang's compiler-rt fuzzer runtime) on the native OFF, OBJ, STL and PLY
#           readers and sanitize_mesh, with AddressSanitizer and UBSan; seed corpus
#           tests/fuzz/corpus/mesh (first byte: 0 OFF, 1 OBJ, 2 STL, 3 PLY).
#   design  tests/fuzz/fuzz_design.py, a mutation fuzzer of Design.load (Python: libFuzzer
#           cannot drive it), seed corpus tests/fuzz/corpus/design; needs build/ (the bindings).
# Work and findings go to build/fuzz/; a crashing input is build/fuzz/crash-* (add it to the
# seed corpus once fixed). Exit status: non-zero if any target found something.
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS_PER_TARGET="${1:-60}"
shift || true
[ $# -gt 0 ] && TARGETS=("$@") || TARGETS=(mesh design)
TIMEOUT="${FUZZ_TIMEOUT:-60}"
OUT="${FUZZ_OUT:-build/fuzz}"
mkdir -p "$OUT/corpus-mesh"
status=0
for target in "${TARGETS[@]}"; do
  case "$target" in
    mesh)
      SOURCES=(native/stripweave/io/mesh_text.cpp native/stripweave/io/polygon_triangulation.cpp
               native/stripweave/io/read_off.cpp native/stripweave/io/read_obj.cpp native/stripweave/io/read_stl.cpp
               native/stripweave/io/read_ply.cpp
               native/stripweave/surface/sanitize_mesh.cpp native/stripweave/surface/outlier_vertices.cpp
               native/stripweave/surface/weld_vertices.cpp
               native/stripweave/surface/mesh_topology.cpp)
      clang++ -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
        -Inative -I/usr/include/eigen3 tests/fuzz/fuzz_mesh_readers.cpp "${SOURCES[@]}" -o "$OUT/fuzz_mesh_readers"
      # Work corpus in build/fuzz (grows), seeds read from the repo (never written).
      KEEP_GOING=()
      [ "${FUZZ_KEEP_GOING:-0}" = 1 ] && KEEP_GOING=(-fork=1 -ignore_timeouts=1)
      "$OUT/fuzz_mesh_readers" "$OUT/corpus-mesh" tests/fuzz/corpus/mesh -max_total_time="$SECONDS_PER_TARGET" \
        "${KEEP_GOING[@]}" -timeout="$TIMEOUT" -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$OUT/" -print_final_stats=1 || status=1
      ;;
    design)
      /usr/bin/python3 tests/fuzz/fuzz_design.py --seconds "$SECONDS_PER_TARGET" --timeout "$TIMEOUT" \
        --findings "$OUT/design-findings" || status=1
      ;;
    *) echo "run.sh: unknown target '$target' (mesh, design)" >&2; exit 2 ;;
  esac
done
exit $status
