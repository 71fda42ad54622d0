#!/usr/bin/env bash
# `mpiexec -n 2 khz prep` with rank 1 killed (SIGKILL) while it computes a product: the job ends
# with the launcher's error naming the rank and rank 0's own, the cache keeps only complete
# products, and the next preparation (one process) computes what is missing and leaves no
# temporary file behind.
# Usage: killed_rank_prep.sh MPIEXEC "MPIEXEC_FLAGS" KHZ SCENE SCRATCH_DIRECTORY
set -u
mpiexec=$1 flags=$2 khz=$3 scene=$4 scratch=$5
cache=$scratch/cache
rm -rf "$scratch" && mkdir -p "$cache"
fail() { echo "FAILED: $*"; cat "$scratch/job.log"; exit 1; }

# shellcheck disable=SC2086  # the flags are several words
"$mpiexec" -n 2 $flags "$khz" prep "$scene" --cache "$cache" >"$scratch/job.log" 2>&1 &
launcher=$!

# The first round (the dino's model and field, the bunny's field) writes four files; then rank 1
# computes the bunny's pointshell, the scene's longest product, for seconds.
for _ in $(seq 600); do
  [ "$(find "$cache" -maxdepth 1 -type f ! -name '*.partial-*' | wc -l)" -ge 4 ] && break
  kill -0 "$launcher" 2>/dev/null || fail "the job ended before its second round"
  sleep 0.1
done
sleep 1
rank1=""
for pid in $(pgrep -f "$khz prep"); do
  if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
    rank1=$pid
  fi
done
[ -n "$rank1" ] || fail "rank 1 not found"
kill -KILL "$rank1"
wait "$launcher" && fail "the job succeeded with a killed rank"
grep -q "rank 1" "$scratch/job.log" || fail "the job's error does not name rank 1"
grep -q "khz: stopped by the MPI launcher" "$scratch/job.log" || fail "rank 0 did not say why it ended"
ls "$cache"/pointshell-*.khzshell >/dev/null 2>&1 && fail "a pointshell file from the killed rank"

"$khz" prep "$scene" --cache "$cache" >"$scratch/again.log" 2>&1 || fail "khz prep afterwards"
grep -q "pointshell .*computed" "$scratch/again.log" || fail "the pointshell was not computed"
find "$cache" -name '*.partial-*' | grep -q . && fail "temporary files left: $(ls "$cache")"
echo "killed rank: the job failed naming rank 1, no partial product was kept"
