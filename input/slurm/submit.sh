#!/bin/bash
# Submit a supratrans study to Slurm: a job array of N slices and a merge job that runs when all succeeded.
#
#   bash input/slurm/submit.sh NAMELIST N [THROTTLE] [--costs EARLIER.h5] [-- sbatch options of the array job]
#
#   NAMELIST   the study (e.g. input/bif1.nml); its output path is relative to this directory
#   N          number of slices (array tasks); THROTTLE: at most this many run at once (default: N)
#   --costs    deal the slices by the task costs measured in EARLIER.h5, an earlier output (or merged file) of the
#              same study, instead of the estimate (supratrans --costs; copied into the study's directory)
#   -- ...     options for the array job (e.g. --time=04:00:00 --dependency=afterok:123 --account=x); the merge
#              job gets only --account, --partition and --qos of them, and always afterok on the array
#
# At submission: the namelist is checked (supratrans --check) and copied into the study's directory
# (<output>.slurm/, beside the output), and the jobs read that copy, so an edit of the namelist afterwards changes
# nothing; the executable is found once (SUPRATRANS, else supratrans on PATH, else the fpm release build, built
# here once if needed) and handed to the jobs by its absolute path; --mem follows the memory estimate of --check;
# an existing output without overwrite = .true. is refused. Logs: <output>.slurm/slice-I.out (a resubmitted or
# requeued slice appends to its log) and merge.out. Prints the two job ids.
#
# A slice that failed is resubmitted with
#   sbatch --array=I input/slurm/supratrans-array.sbatch COPY N EXECUTABLE      (it resumes from its journal)
# and the merge with
#   sbatch input/slurm/supratrans-merge.sbatch COPY N EXECUTABLE
# (COPY and EXECUTABLE as this script prints them).
#
# Numbers (N, THROTTLE, --cpus-per-task, the memory --check reports) are checked as text before any arithmetic:
# decimal digits without a leading zero, no larger than their bound. Runs under bash 4.2 and later (set -u: an
# empty array is expanded as ${a[@]+"${a[@]}"}).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
usage() {
    sed -n '2,24p' "${BASH_SOURCE[0]}" >&2
    exit 2
}
die() {
    echo "submit.sh: $*" >&2
    exit 2
}
# decimal WHAT TEXT MAX [MIN]: TEXT must be a decimal literal from MIN (1, or 0) to MAX, checked as text before it
# reaches any arithmetic: in $(( )) or (( )) bash evaluates its operands as expressions, and `i[$(cmd)]` runs cmd;
# a leading zero reads as octal (08 is an error, 010 is 8); a number longer than 19 digits wraps around. So: digits
# only, no leading zero, and the length compared before the value (as text: equal lengths order as numbers).
decimal() {
    local what=$1 text=$2 max=$3 min=${4:-1} pattern='^[1-9][0-9]*$'
    [[ ${min} == 0 ]] && pattern='^(0|[1-9][0-9]*)$'
    if ! [[ ${text} =~ ${pattern} ]] || ((${#text} > ${#max})) || { ((${#text} == ${#max})) && [[ ${text} > ${max} ]]; }; then
        die "${what} = '${text}': expected a decimal number from ${min} to ${max} (digits only, no leading zero)"
    fi
}
(($# >= 2)) || usage
namelist=$1
slices=$2
shift 2
throttle=${slices}
if (($# > 0)) && [[ $1 != "--" && $1 != "--costs" ]]; then
    throttle=$1
    shift
fi
costs=""
if (($# > 0)) && [[ $1 == "--costs" ]]; then
    (($# > 1)) || die "--costs needs a file (an earlier output of the same study)"
    costs=$2
    shift 2
    [[ -f ${costs} && -r ${costs} ]] || die "--costs ${costs}: no such readable file"
fi
if (($# > 0)); then
    [[ $1 == "--" ]] || die "unexpected argument '$1' (sbatch options go after --)"
    shift
fi
array_opts=()
if (($# > 0)); then
    array_opts=("$@")
fi
[[ -f ${namelist} ]] || die "${namelist}: no such namelist file"
decimal N "${slices}" 100000
decimal THROTTLE "${throttle}" 100000

# the executable, once, by its absolute path
exe=${SUPRATRANS:-}
if [[ -z ${exe} ]]; then
    exe=$(command -v supratrans || true)
fi
if [[ -z ${exe} ]]; then
    root=$(cd "${here}/../.." && pwd)
    if command -v fpm >/dev/null && [[ -f ${root}/fpm.toml ]]; then
        echo "submit.sh: no supratrans on PATH and SUPRATRANS unset: building the release once in ${root}" >&2
        (cd "${root}" && sh .ci/with_commit fpm build --profile release >&2) || die "the release build failed"
        exe=$(cd "${root}" && fpm run --profile release --runner echo supratrans 2>/dev/null | tail -n 1)
        [[ -n ${exe} && ${exe} != /* ]] && exe=${root}/${exe}
    fi
fi
[[ -n ${exe} ]] || die "no executable: set SUPRATRANS=/path/to/supratrans, or put supratrans on PATH"
given=${exe}
if [[ ${exe} != */* ]]; then
    exe=$(command -v "${exe}" || true)
fi
[[ -n ${exe} && -f ${exe} && -x ${exe} ]] || die "${given}: not an executable file (SUPRATRANS, or supratrans on PATH)"
exe=$(cd "$(dirname "${exe}")" && pwd)/$(basename "${exe}")

# the namelist, checked, then its output, overwrite rule and memory from what --check says
report=$("${exe}" --check "${namelist}") || die "${namelist} does not pass supratrans --check (the line above)"
value() { sed -n "s/^$1 //p" <<<"${report}" | head -n 1; }
output=$(value output)
overwrite=$(value overwrite)
scene=$(value scene)
per_thread=$(value memory_per_thread_bytes)
[[ -n ${output} && -n ${overwrite} && -n ${per_thread} ]] || die "${exe} --check printed no output and memory (an older supratrans?)"
decimal "the memory per thread of ${exe} --check" "${per_thread}" 100000000000000 0
[[ ${scene} != timeseries ]] || die "${namelist}: a timeseries is one run, it is not sliced (run it with sbatch directly)"
if [[ -e ${output} && ${overwrite} != 1 ]]; then
    die "${output}: output file exists (set overwrite = .true. in ${namelist} to replace it, or move it away)"
fi

# the study's directory beside the output: the namelist copy the tasks read, and the logs
study_dir=${output%.h5}.slurm
mkdir -p "${study_dir}"
name=$(basename "${output%.h5}")
copy=${study_dir}/${name}-$(cksum <"${namelist}" | cut -d ' ' -f 1).nml
if [[ ! -f ${copy} ]] || ! cmp -s "${namelist}" "${copy}"; then
    cp "${namelist}" "${copy}.tmp.$$"
    mv -f "${copy}.tmp.$$" "${copy}"
fi
# the measured costs, copied too: every slice reads the same bytes (a later run may replace the original)
costs_args=()
if [[ -n ${costs} ]]; then
    costs_copy=${study_dir}/costs-$(cksum <"${costs}" | cut -d ' ' -f 1).h5
    if [[ ! -f ${costs_copy} ]] || ! cmp -s "${costs}" "${costs_copy}"; then
        cp "${costs}" "${costs_copy}.tmp.$$"
        mv -f "${costs_copy}.tmp.$$" "${costs_copy}"
    fi
    costs_args=("${costs_copy}")
fi

# options: the user's (after --) go to the array; the merge gets account, partition, qos; a user's --dependency
# stays with the array and is combined with the merge's own afterok
merge_opts=()
user_dep=""
user_mem=0
cpus=""
i=0
while ((i < ${#array_opts[@]})); do
    opt=${array_opts[i]}
    next=${array_opts[i + 1]:-}
    case ${opt} in
    --account=* | --partition=* | --qos=*) merge_opts+=("${opt}") ;;
    -A?* | -p?* | -q?*) merge_opts+=("${opt}") ;;
    --account | --partition | --qos | -A | -p | -q)
        merge_opts+=("${opt}" "${next}")
        ;;
    --dependency=*) user_dep=${opt#--dependency=} ;;
    -d?*) user_dep=${opt#-d} ;;
    --dependency | -d) user_dep=${next} ;;
    --mem=* | --mem-per-cpu=* | --mem-per-gpu=* | --mem | --mem-per-cpu | --mem-per-gpu) user_mem=1 ;;
    --cpus-per-task=*) cpus=${opt#--cpus-per-task=} ;;
    -c?*) cpus=${opt#-c} ;;
    --cpus-per-task | -c) cpus=${next} ;;
    esac
    i=$((i + 1))
done
if [[ -z ${cpus} ]]; then
    cpus=$(sed -n 's/^#SBATCH --cpus-per-task=\([0-9]*\).*/\1/p' "${here}/supratrans-array.sbatch" | head -n 1)
fi
cpus=${cpus:-1}
decimal "--cpus-per-task" "${cpus}" 10000
mem_opts=()
if ((user_mem == 0)); then
    # the runs' own memory (twice the estimate: work arrays, the task results) and the program's libraries
    mem_mb=$((256 + (2 * per_thread * cpus + 1048575) / 1048576))
    mem_opts=("--mem=${mem_mb}M")
fi

array=$(sbatch --parsable --job-name="supratrans-${name}" --array="1-${slices}%${throttle}" \
    --output="${study_dir}/slice-%a.out" --open-mode=append ${mem_opts[@]+"${mem_opts[@]}"} \
    ${array_opts[@]+"${array_opts[@]}"} "${here}/supratrans-array.sbatch" "${copy}" "${slices}" "${exe}" \
    ${costs_args[@]+"${costs_args[@]}"})
array=${array%%;*}
dep="afterok:${array}"
if [[ -n ${user_dep} && ${user_dep} != *"?"* ]]; then
    dep="${dep},${user_dep}"
fi
merge=$(sbatch --parsable --job-name="supratrans-merge-${name}" --dependency="${dep}" --kill-on-invalid-dep=yes \
    --output="${study_dir}/merge.out" --open-mode=append ${merge_opts[@]+"${merge_opts[@]}"} \
    "${here}/supratrans-merge.sbatch" "${copy}" "${slices}" "${exe}")
merge=${merge%%;*}
echo "namelist copy ${copy}, executable ${exe}${costs:+, costs ${costs_copy}}" >&2
echo "array job ${array} (${slices} slices of ${namelist}), merge job ${merge}"
