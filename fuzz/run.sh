#!/usr/bin/env bash
# Runs the keyword reader's fuzz target (built by `cmake --build --preset fuzz`) for a bounded time.
#   fuzz/run.sh SECONDS WORKDIR [libFuzzer options...]
# WORKDIR receives the seeds (every .k deck of the repository and of ../shared/decks, fuzz/seeds,
# fuzz/corpus, fuzz/regressions), the growing corpus and any crash input; the fuzzer runs in an
# empty folder there, so that a fuzzed *INCLUDE finds nothing of the repository's.
set -euo pipefail
seconds=${1:?seconds}
work=$(realpath -m "${2:?work folder}")
shift 2
repo=$(cd "$(dirname "$0")/.." && pwd)
fuzzer="$repo/build/fuzz/bin/keyword_fuzz"
mkdir -p "$work/seeds" "$work/corpus" "$work/artifacts" "$work/cwd"
# Named by their content's hash, as libFuzzer names its corpus: a deck found twice is one seed.
while IFS= read -r -d '' deck; do
  cp "$deck" "$work/seeds/$(sha1sum < "$deck" | cut -c1-40)"
done < <(find "$repo/examples" "$repo/bench" "$repo/tests" "$repo/../shared/decks" "$repo/fuzz/seeds" \
           "$repo/fuzz/corpus" "$repo/fuzz/regressions" -type f \( -name '*.k' -o -path '*/fuzz/*' \) \
           -print0 2>/dev/null)
cd "$work/cwd"
exec "$fuzzer" -dict="$repo/fuzz/keywords.dict" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
  -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$work/artifacts/" "$@" \
  "$work/corpus" "$work/seeds"
