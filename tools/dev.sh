#!/usr/bin/env bash
# The two quick-start jobs. Each installs what pushpin needs (tools/setup.sh, idempotent), builds
# in ./build (Release, -O2) and then:
#   tools/dev.sh demo   runs the main job on the built-in demo scene
#   tools/dev.sh test   fuzzes the readers and the whole frame under ASan/UBSan for a bounded time, then runs every test
set -euo pipefail

job="${1:-}"
case "$job" in
  demo|test) ;;
  *) echo "usage: tools/dev.sh demo|test" >&2; exit 2 ;;
esac

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash tools/setup.sh

jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"

if [ "$job" = demo ]; then
  echo "== pushpin --demo (renders the built-in scene into build/images)"
  ./build/pushpin --demo -rd build/images --stats build/images/softSpotlight-stats.json
  exit 0
fi

# Fuzzing: libFuzzer targets built with clang, AddressSanitizer and UndefinedBehaviorSanitizer.
# Seeds are copied into a temporary folder; the project tree is never written to.
fuzz_seconds="${PUSHPIN_FUZZ_SECONDS:-120}"
if command -v clang++ >/dev/null 2>&1; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPUSHPIN_FUZZ=ON -DPUSHPIN_SANITIZE=ON -DPUSHPIN_BUILD_TESTS=OFF -DPUSHPIN_BUILD_BENCH=OFF
  fuzz_targets=$(cd tests/fuzz && ls *_fuzz.cpp 2>/dev/null | sed 's/\.cpp$//' || true)
  if [ -n "$fuzz_targets" ]; then
    cmake --build build-fuzz -j"$jobs" --target $fuzz_targets
    seeds="$(mktemp -d)"
    trap 'rm -rf "$seeds"' EXIT
    corpus="$(cd "$root/.." && pwd)/shared/scenes/ma-public"
    for target in $fuzz_targets; do
      mkdir -p "$seeds/$target"
      if { [ "$target" = ma_reader_fuzz ] || [ "$target" = render_fuzz ]; } && [ -d "$corpus" ]; then
        cp "$corpus"/*.ma "$seeds/$target/"
        ./build/pushpin --print-demo > "$seeds/$target/demo.ma"
      fi
      echo "== fuzzing $target for ${fuzz_seconds}s"
      log="$seeds/$target.log"
      if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
          "./build-fuzz/fuzz/$target" -max_total_time="$fuzz_seconds" -max_len=65536 -rss_limit_mb=4096 \
          -artifact_prefix="$seeds/" -print_final_stats=1 "$seeds/$target" > "$log" 2>&1; then
        tail -n 60 "$log"
        echo "fuzz target $target failed" >&2
        exit 1
      fi
      tail -n 12 "$log"
    done
  fi
else
  echo "clang++ not found: skipping the libFuzzer stage" >&2
fi

echo "== tests"
ctest --test-dir build --output-on-failure -j"$jobs"
