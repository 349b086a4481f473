#!/usr/bin/env bash
# Sanitizer build of supratrans: the Fortran suite and one small run of every scene, built with
#   -fsanitize=address,undefined -fcheck=all -g
# (AddressSanitizer with leak detection, UndefinedBehaviorSanitizer, gfortran's run-time checks of bounds,
# pointers, recursion, array temporaries and do-loop counts). Any finding makes a sanitizer report on stderr
# and a non-zero exit status; this script ends with `sanitize: N passed, M failed` and exits non-zero iff M > 0.
# Usage: bash test/sanitize.sh            (about 3-5 minutes on 2 cores; separate build directory)
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1

flags="-fsanitize=address,undefined -fcheck=all -fno-omit-frame-pointer -g -O1"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:exitcode=86"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=87"
export OMP_NUM_THREADS=2
passed=0
failed=0
tmp=$(mktemp -d)
trap 'rm -rf "${tmp}"' EXIT

check() {   # check NAME LOG STATUS: a step passes when it exited 0 and its log holds no sanitizer report
    local name=$1 log=$2 status=$3
    if ((status == 0)) && ! grep -qE 'ERROR: (Address|Leak)Sanitizer|runtime error:|Fortran runtime error|Fortran runtime warning' "${log}"; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
        echo "sanitize: FAILED: ${name} (exit ${status}); log:"
        grep -E -m 20 -A 12 'ERROR: |runtime error|Fortran runtime' "${log}" || tail -n 20 "${log}"
    fi
}

python3 test/pf2f90.py || { echo "sanitize: 0 passed, 1 failed"; exit 1; }
fpm test --flag "${flags}" >"${tmp}/suite.log" 2>&1
check "fpm test" "${tmp}/suite.log" $?
grep -E '^fortran: ' "${tmp}/suite.log" | tail -n 1

exe=$(fpm run --flag "${flags}" --runner echo 2>/dev/null | tail -n 1)
if [[ ! -x ${exe} ]]; then
    echo "sanitize: 0 passed, 1 failed (no executable)"
    exit 1
fi

# One small run of every scene: a short chain, short T, tiny grids.
small="&chain n = 60, n0 = 45 /
&numerics t_final = 20.0 /
&record probes = 5, 30 /"
declare -A scenes=(
    [timeseries]="&scene kind = 'timeseries' /"
    [amplitude_sweep]="&scene kind = 'amplitude_sweep', amplitude_min = 1.0, amplitude_max = 2.0, amplitude_step = 0.5,
    vary = 'gamma', values = 0.0, 0.01 /"
    [map]="&scene kind = 'map', amplitude_min = 1.0, amplitude_max = 2.0, amplitude_step = 0.5, omega_min = 0.6,
    omega_max = 0.9, omega_step = 0.15 /"
    [bifurcation]="&scene kind = 'bifurcation', amplitude_min = 0.5, amplitude_max = 4.0, omega_min = 0.7,
    omega_max = 0.9, omega_step = 0.1, coarse_step = 0.5, resolution = 0.1, potentials = 'sine-gordon', 'klein-gordon' /"
    [work_precision]="&scene kind = 'work_precision', methods = 'newton', 'rk4', dts = 0.1, 0.05, repeats = 1,
    reference_dt = 0.05 /"
    [stability]="&scene kind = 'stability', methods = 'newton', 'linearized', dts = 0.2, 0.26, resolution = 0.02 /"
)
for scene in timeseries amplitude_sweep map bifurcation work_precision stability; do
    printf '%s\n%s\n&output file = "%s/%s.h5", quiet = .true. /\n' "${small}" "${scenes[${scene}]}" "${tmp}" "${scene}" \
        >"${tmp}/${scene}.nml"
    "${exe}" "${tmp}/${scene}.nml" >"${tmp}/${scene}.log" 2>&1
    check "scene ${scene}" "${tmp}/${scene}.log" $?
done
# Bad input and the command line itself (the error paths free what they allocate too).
printf '&chain cc = 4 /\n' >"${tmp}/bad.nml"
"${exe}" "${tmp}/bad.nml" >"${tmp}/bad.log" 2>&1
status=$?
((status == 2)) && status=0
check "bad input" "${tmp}/bad.log" ${status}

echo "sanitize: ${passed} passed, ${failed} failed"
((failed == 0))
