#!/usr/bin/env bash
# A phase study (`slither phase`) as a Slurm job array: N array tasks, task I running shard I/N
# into OUT/shard_I, then one merge job (started only when every task succeeded,
# --dependency=afterok) writing the combined phase.csv, boundaries.json and figures to
# OUT/merged. Prints the two job ids ("array JOBID" and "merge JOBID") and returns at once;
# watch them with `squeue`.
#
# Usage: tools/slurm/phase_array.sh PHASE.toml OUT N [extra sbatch options...]
#
# Environment:
#   SLITHER        the slither binary (default: `slither` on PATH); must be visible on the nodes
#   CPUS_PER_TASK  cores per array task (default 1); each task runs its cells on that many
#                  rayon threads (RAYON_NUM_THREADS)
# Extra options (e.g. --partition=short --time=02:00:00) go to both sbatch calls.
# Every task is resumable: resubmitting with the same OUT simulates only the cells missing.
set -euo pipefail

if [ $# -lt 3 ]; then
    echo "usage: $0 PHASE.toml OUT N [sbatch options...]" >&2
    exit 2
fi
phase=$(realpath "$1")
out=$(realpath -m "$2")
n=$3
shift 3
case "$n" in
    '' | *[!0-9]* | 0)
        echo "$0: N must be a positive integer (got '$n')" >&2
        exit 2
        ;;
esac
bin=${SLITHER:-$(command -v slither || true)}
if [ -z "$bin" ] || [ ! -x "$bin" ]; then
    echo "$0: no slither binary (set SLITHER=/path/to/slither or put it on PATH)" >&2
    exit 2
fi
cpus=${CPUS_PER_TASK:-1}
mkdir -p "$out/logs"

q_bin=$(printf %q "$bin")
q_phase=$(printf %q "$phase")
q_out=$(printf %q "$out")

array=$(sbatch --parsable --array=1-"$n" --cpus-per-task="$cpus" --job-name=slither-phase \
    --chdir="$out" --output="$out/logs/shard_%a.log" "$@" <<JOB
#!/usr/bin/env bash
set -euo pipefail
export RAYON_NUM_THREADS=\${SLURM_CPUS_PER_TASK:-1}
exec $q_bin phase $q_phase --out $q_out/shard_\${SLURM_ARRAY_TASK_ID} \\
    --shard \${SLURM_ARRAY_TASK_ID}/$n --quiet
JOB
)
array=${array%%;*}

shards=""
for i in $(seq 1 "$n"); do
    shards="$shards $q_out/shard_$i"
done
merge=$(sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
    --job-name=slither-merge --chdir="$out" --output="$out/logs/merge.log" "$@" <<JOB
#!/usr/bin/env bash
set -euo pipefail
exec $q_bin merge$shards --out $q_out/merged
JOB
)
merge=${merge%%;*}
echo "array $array"
echo "merge $merge"
