#!/bin/bash
# Submit a supratrans study to Slurm: a job array of N slices and a merge job that runs when all succeeded.
#
#   bash input/slurm/submit.sh NAMELIST N [THROTTLE] [-- extra sbatch options]
#
#   NAMELIST   the study (e.g. input/bif1.nml); its output path is relative to this directory
#   N          number of slices (array tasks); THROTTLE: at most this many run at once (default: N)
#
# Prints the two job ids. A slice that timed out or was cancelled is resubmitted with
#   sbatch --array=I input/slurm/supratrans-array.sbatch NAMELIST N     (it resumes from its journal)
# and the merge with
#   sbatch input/slurm/supratrans-merge.sbatch NAMELIST N
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if (($# < 2)); then
    sed -n '2,14p' "${BASH_SOURCE[0]}" >&2
    exit 2
fi
namelist=$1
slices=$2
throttle=${3:-$2}
shift $(($# >= 3 ? 3 : 2))
[[ ${1:-} == "--" ]] && shift
if [[ ! -f ${namelist} ]]; then
    echo "submit.sh: ${namelist}: no such namelist file" >&2
    exit 2
fi
if ! [[ ${slices} =~ ^[0-9]+$ && ${throttle} =~ ^[0-9]+$ ]] || ((slices < 1 || throttle < 1)); then
    echo "submit.sh: N and THROTTLE must be positive integers" >&2
    exit 2
fi
array=$(sbatch --parsable --array="1-${slices}%${throttle}" "$@" "${here}/supratrans-array.sbatch" "${namelist}" \
    "${slices}")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:${array}" --kill-on-invalid-dep=yes "$@" \
    "${here}/supratrans-merge.sbatch" "${namelist}" "${slices}")
merge=${merge%%;*}
echo "array job ${array} (${slices} slices of ${namelist}), merge job ${merge}"
