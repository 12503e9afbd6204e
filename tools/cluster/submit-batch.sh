#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Submits a batch as a Slurm job array of SHARDS tasks plus the dependent merge job; prints the
# two job ids. Extra sbatch options (partition, account, time) go in $SBATCH_OPTS.
#   tools/cluster/submit-batch.sh SHARDS FOLDER [coxswain-sim batch args...]
#   tools/cluster/submit-batch.sh 16 /shared/obstacle-1000 --kind obstacle --runs 1000
set -euo pipefail
shards=${1:?usage: submit-batch.sh SHARDS FOLDER [batch args...]}
folder=${2:?usage: submit-batch.sh SHARDS FOLDER [batch args...]}
shift 2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$folder"
# shellcheck disable=SC2086
array=$(sbatch --parsable ${SBATCH_OPTS:-} --array=0-$(( shards - 1 )) \
  --output="$folder/slurm-%A_%a.out" "$here/batch.sbatch" shard "$folder" "$@")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_OPTS:-} --dependency=afterok:"$array" \
  --output="$folder/slurm-merge-%j.out" "$here/batch.sbatch" merge "$folder")
merge=${merge%%;*}
echo "array $array merge $merge"
