#!/usr/bin/env bash
# Runs the fuzz targets of a fuzz tree one after another, each for SECONDS, under the limits of
# fuzz/CMakeLists.txt, and prints executions, coverage and findings per target at the end.
#
#   fuzz/run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]        (make fuzz)
#
# Corpus: BUILD_DIR/corpus/<target> (kept and grown between runs), seeded from BUILD_DIR/seeds/<target>
# (fuzz/make_corpus.sh). Findings (crash-*, leak-*, timeout-*, oom-*): $FUZZ_FINDINGS/<target>/,
# default fuzz/findings/<target>/, each with a .txt beside it holding the replayed sanitizer report.
# libFuzzer runs in fork mode (one job at a time, -fork=${FUZZ_JOBS:-1}) and carries on after a
# finding, so one bug does not end a target's time; one input is kept per distinct bug (index.tsv).
# Dictionaries: fuzz/dicts/<target>.dict (plus numbers.dict, json.dict). Logs: BUILD_DIR/fuzz-logs/.
# Exit status: 1 when a target found something (or failed to run), else 0.
set -uo pipefail

build=${1:?usage: fuzz/run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]}
seconds=${2:?usage: fuzz/run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]}
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$build" && pwd)
findings=${FUZZ_FINDINGS:-$root/fuzz/findings}
jobs=${FUZZ_JOBS:-1}
limits=(-rss_limit_mb=1024 -malloc_limit_mb=1024 -timeout=1)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

if [[ $# -gt 0 ]]; then
  targets=("$@")
else
  mapfile -t targets < <(cd "$build/bin" && ls fuzz_* 2>/dev/null | sort)
fi
[[ ${#targets[@]} -gt 0 ]] || { echo "run_fuzzers: no fuzz_* in $build/bin (build the fuzz_targets target)" >&2; exit 1; }
mkdir -p "$build/fuzz-logs"

json_targets="fuzz_mask_json fuzz_vocabulary fuzz_alias_table fuzz_dense_model fuzz_run_config fuzz_sim_config"
binary_targets="fuzz_png fuzz_velodyne_scan fuzz_semantic_labels"
summary=()
status=0
for t in "${targets[@]}"; do
  bin=$build/bin/$t
  [[ -x $bin ]] || { echo "run_fuzzers: $bin missing" >&2; summary+=("$(printf '%-24s not built' "$t")"); status=1; continue; }
  corpus=$build/corpus/$t
  seeds=$build/seeds/$t
  mkdir -p "$corpus" "$findings/$t" "$seeds"
  log=$build/fuzz-logs/$t.log
  # Dictionary: the format's keywords (fuzz/dicts/<target>.dict), edge-case numbers for text
  # formats, JSON's structure for JSON formats.
  dict=()
  if [[ -f $root/fuzz/dicts/$t.dict ]]; then
    mkdir -p "$build/dicts"
    parts=("$root/fuzz/dicts/$t.dict")
    [[ " $binary_targets " == *" $t "* ]] || parts+=("$root/fuzz/dicts/numbers.dict")
    [[ " $json_targets " == *" $t "* ]] && parts+=("$root/fuzz/dicts/json.dict")
    cat "${parts[@]}" >"$build/dicts/$t.dict"
    dict=(-dict="$build/dicts/$t.dict")
  fi
  echo "=== $t: ${seconds} s (log: $log)"
  "$bin" -fork="$jobs" -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -max_total_time="$seconds" \
    "${limits[@]}" "${dict[@]}" -print_final_stats=1 -artifact_prefix="$findings/$t/" "$corpus" "$seeds" >"$log" 2>&1
  rc=$?
  # Fork mode's progress lines: "#123456: cov: 812 ft: 2403 corp: 301 exec/s 4115 oom/timeout/crash: 0/0/1 ...".
  last=$(grep -E '^#[0-9]+: cov: ' "$log" | tail -n 1)
  execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$last")
  cov=$(sed -E 's/.* cov: ([0-9]+).*/\1/' <<<"$last")
  ft=$(sed -E 's/.* ft: ([0-9]+).*/\1/' <<<"$last")
  corp=$(sed -E 's/.* corp: ([0-9]+).*/\1/' <<<"$last")
  # Executions per second over the whole run (fork mode's own figure is the last job's).
  eps=$( [[ $execs =~ ^[0-9]+$ ]] && echo $((execs / seconds)) || echo "?")
  otc=$(sed -E 's/.* oom\/timeout\/crash: ([0-9]+\/[0-9]+\/[0-9]+).*/\1/' <<<"$last")
  # Replay each new finding once, keeping its report beside it (<finding>.txt), and keep one input
  # per distinct bug: fork mode finds the same bug again in every job. A bug's signature is the
  # sanitizer's (or libFuzzer's, or the harness's) kind of error and the first stack frame in src/
  # or apps/ (else in the harness); index.tsv lists the kept inputs with their signatures.
  index=$findings/$t/index.tsv
  touch "$index"
  kept=()
  dups=0
  replayed=0
  skipped=0
  while IFS= read -r f; do
    grep -qF "$(basename "$f")" "$index" && continue
    if ((replayed >= ${FUZZ_MAX_REPLAYS:-100})); then
      skipped=$((skipped + 1))
      continue
    fi
    replayed=$((replayed + 1))
    timeout 60 "$bin" "${limits[@]}" "$f" >"$f.txt" 2>&1
    kind=$(grep -m1 -oE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer): [a-z-]+|[^ ]+: runtime error|fuzz invariant broken: [^:]*' "$f.txt")
    frame=$( (grep -E '^ *#[0-9]+ 0x[0-9a-f]+ in .*/(src|apps)/' "$f.txt"; grep -E '^ *#[0-9]+ 0x[0-9a-f]+ in .*/fuzz/fuzz_[a-z_]+\.cpp' "$f.txt") |
      head -n 1 | sed -E 's/^ *#[0-9]+ 0x[0-9a-f]+ in //')
    sig="${kind:-no report on replay} @ ${frame:-?}"
    if cut -f2 "$index" | grep -qxF "$sig"; then
      rm -f "$f" "$f.txt"
      dups=$((dups + 1))
    else
      printf '%s\t%s\n' "$(basename "$f")" "$sig" >>"$index"
      kept+=("$(basename "$f"): $sig")
    fi
  done < <(find "$findings/$t" -maxdepth 1 -type f -regex '.*/\(crash\|leak\|timeout\|oom\|slow-unit\)-[0-9a-f]*' | sort)
  # Scratch folders of fuzzing processes that crashed or were killed (fuzz_common.hpp).
  for d in /dev/shm/artemis-fuzz-* "${TMPDIR:-/tmp}"/artemis-fuzz-*; do
    [[ -d $d && ${d##*-} =~ ^[0-9]+$ ]] && ! kill -0 "${d##*-}" 2>/dev/null && rm -rf "$d"
  done
  # Nothing found: leave no empty folder behind in the source tree.
  [[ -s $index ]] || rm -f "$index"
  rmdir "$findings/$t" 2>/dev/null
  [[ -z $last ]] && { execs=?; cov=?; ft=?; corp=?; eps=?; otc=?; }
  line=$(printf '%-24s execs %10s  exec/s %6s  cov %5s  ft %6s  corpus %5s  oom/timeout/crash %-8s  new bugs %d (+%d duplicates)' \
    "$t" "$execs" "$eps" "$cov" "$ft" "$corp" "$otc" "${#kept[@]}" "$dups")
  summary+=("$line")
  for k in "${kept[@]}"; do summary+=("    $k"); done
  if [[ -z $last || ${#kept[@]} -gt 0 ]]; then status=1; fi
  [[ -z $last ]] && summary+=("    libFuzzer printed no progress (exit $rc): see $log")
  ((skipped > 0)) && summary+=("    $skipped more inputs not replayed (FUZZ_MAX_REPLAYS): see $findings/$t")
done

rmdir "$findings" 2>/dev/null
echo
echo "=== Fuzzing summary (${seconds} s per target; findings in $findings)"
printf '%s\n' "${summary[@]}"
exit $status
