#!/usr/bin/env bash
# Run the whole test suite of supratrans from any directory:
#   1. .ci/install (installs only what is missing),
#   2. test/pf2f90.py: test/X.pf -> test/X.f90 + test/pf_driver.f90 (pFUnit syntax -> Fortran;
#      they must sit next to test/pf_runtime.f90, the only place fpm lets them use it from),
#   3. fpm test (debug profile), which prints `fortran: N passed, M failed`, with the commit's C flags of
#      .ci/with_commit (the build records the commit, as conftest.py's builds for pytest do), while the release and
#      host builds of the Python tests compile beside it,
#   4. pytest on test/ and postprocess/, on every core (pytest.ini: pytest-xdist).
# Usage: bash test/run_tests.sh [FILTER]
#   FILTER (optional) runs only the Fortran tests whose `module::test` name contains it.
# Each stage prints its wall time as it ends, and the line before the last sums them up (`run_tests: wall time by
# stage: ...`); the Fortran runner prints each test's time and its slowest ten, `pytest --durations=15` its slowest.
# The fast tier (docs/testing.md): `fpm test` and `python3 -m pytest -m "not slow"`.
# The last line printed is `N passed, M failed`, summed over both suites, where a stage that
# could not run (install, translation, build, crash) counts as one failure. Exit status 0 iff
# M == 0.
set -uo pipefail   # no -e: every stage runs and its failure is counted
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1

passed=0
failed=0
tmp=$(mktemp -d)
trap 'rm -rf "${tmp}"' EXIT

note() {
    echo "run_tests: $*"
}

# Each stage's wall time, printed when it ends (`run_tests: <stage>: N s`) and again in one line before the total:
# where the suite's time goes (reporting only).
stage_start=${SECONDS}
stage_times=()
stage_done() {
    local took=$((SECONDS - stage_start))
    note "$1: ${took} s"
    stage_times+=("$1 ${took} s")
    stage_start=${SECONDS}
}

# ----------------------------------------------------------------------------- 1. install
if ! bash .ci/install; then
    note "FAILED: .ci/install"
    failed=$((failed + 1))
fi
stage_done install

# ----------------------------------------------------------------------------- generated files
if ! python3 src/io/generate_schema.py --check; then
    note "FAILED: generated files are stale (run python3 src/io/generate_schema.py)"
    failed=$((failed + 1))
fi
if ! python3 src/io/generate_outputs.py --check; then
    note "FAILED: files generated from the output tables are stale (run python3 src/io/generate_outputs.py)"
    failed=$((failed + 1))
fi

# ----------------------------------------------------------------------------- 2. translate .pf
# The translation (test/test_*.f90, test/pf_driver.f90) is committed, so that `fpm test` on a fresh clone
# runs every Fortran test; stale committed files fail the suite, and the tests run on a fresh translation.
if ! python3 test/pf2f90.py --check; then
    note "FAILED: the committed translation of test/*.pf is stale: run python3 test/pf2f90.py and commit it"
    failed=$((failed + 1))
fi
translated=1
if ! python3 test/pf2f90.py; then
    note "FAILED: test/pf2f90.py (Fortran tests not run)"
    failed=$((failed + 1))
    translated=0
fi

stage_done "generated files and translation"

# ----------------------------------------------------------------------------- 2b. lint
# fortitude (rules and their reasons in fpm.toml [extra.fortitude.check]); one pass or one failure
if fortitude check --output-format concise src app test/pf_runtime.f90 >"${tmp}/lint.log" 2>&1; then
    passed=$((passed + 1))
else
    cat "${tmp}/lint.log"
    note "FAILED: fortitude check (lint)"
    failed=$((failed + 1))
fi
stage_done lint

# ----------------------------------------------------------------------------- 3. builds and fpm test
# fpm test builds the debug profile and runs the Fortran tests while the release build (make_figures.py's, and the
# Python tests' release_exe) and the host build (HOST_FLAGS of conftest.py, for test_host_build.py) compile beside
# it, so that both cores stay busy through the builds' serial stretches; pytest's fixtures then only relink them. All
# three take the commit's C flags from one .ci/with_commit call, made before any of them starts (it removes the
# library archives of every profile: run inside each build, it could remove one that another build had just made).
commit_flags=$(sh .ci/with_commit sh -c 'printf "%s" "${FPM_CFLAGS:-}"')
host_flags=${SUPRATRANS_HOST_FLAGS:--march=native}
builds=()
FPM_CFLAGS=${commit_flags} fpm build --profile release >"${tmp}/release.log" 2>&1 &
builds+=("$! release ${tmp}/release.log")
FPM_CFLAGS=${commit_flags} fpm build --profile release --flag "${host_flags}" >"${tmp}/host.log" 2>&1 &
builds+=("$! host ${tmp}/host.log")
if ((translated)); then
    fpm_args=(test)
    if (($# > 0)); then
        fpm_args+=(-- "$@")
    fi
    log="${tmp}/fpm.log"
    FPM_CFLAGS=${commit_flags} fpm "${fpm_args[@]}" 2>&1 | tee "${log}"
    status=${PIPESTATUS[0]}
    f_passed=0
    f_failed=0
    summaries=0
    while read -r n_pass n_fail; do
        f_passed=$((f_passed + n_pass))
        f_failed=$((f_failed + n_fail))
        summaries=$((summaries + 1))
    done < <(sed -n -E 's/^fortran: ([0-9]+) passed, ([0-9]+) failed[[:space:]]*$/\1 \2/p' "${log}")
    if ((summaries == 0)); then
        note "FAILED: fpm test printed no 'fortran: N passed, M failed' line (exit status ${status}: build failure or crash)"
        f_failed=$((f_failed + 1))
    elif ((status != 0 && f_failed == 0)); then
        note "FAILED: fpm test exited with status ${status}"
        f_failed=$((f_failed + 1))
    fi
    passed=$((passed + f_passed))
    failed=$((failed + f_failed))
    stage_done "fpm test"
fi
for build in "${builds[@]}"; do
    read -r pid name build_log <<<"${build}"
    if ! wait "${pid}"; then
        # not counted here: the tests that need it fail with fpm's message when pytest builds it again
        tail -n 20 "${build_log}"
        note "the ${name} build failed (its tests will say so)"
    fi
done
stage_done "release and host builds (the rest of them)"

# ----------------------------------------------------------------------------- 4. pytest
# pytest.ini and conftest.py (the program built once per session); every test, the slow end-to-end ones too
# (`python3 -m pytest -m "not slow"` skips those).
py_dirs=()
for dir in test postprocess; do
    if [[ -d ${dir} ]]; then
        py_dirs+=("${dir}")
    fi
done
xml="${tmp}/pytest.xml"
python3 -m pytest -q -p no:cacheprovider --durations=15 --junitxml="${xml}" "${py_dirs[@]}"
status=$?
counts=$(python3 - "${xml}" <<'EOF'
import sys
import xml.etree.ElementTree as ET

try:
    root = ET.parse(sys.argv[1]).getroot()
except (OSError, ET.ParseError):
    print("missing")
    sys.exit()
suites = [root] if root.tag == "testsuite" else root.iter("testsuite")
tests = failures = skipped = 0
for s in suites:
    tests += int(s.get("tests", 0))
    failures += int(s.get("failures", 0)) + int(s.get("errors", 0))
    skipped += int(s.get("skipped", 0))
print(tests - failures - skipped, failures)
EOF
)
if [[ ${counts} == missing ]]; then
    note "FAILED: pytest wrote no report (exit status ${status})"
    failed=$((failed + 1))
else
    read -r p_passed p_failed <<<"${counts}"
    # Exit status 5 means no test was collected, which is not a failure.
    if ((status != 0 && status != 5 && p_failed == 0)); then
        note "FAILED: pytest exited with status ${status}"
        p_failed=1
    fi
    passed=$((passed + p_passed))
    failed=$((failed + p_failed))
fi
stage_done pytest
note "wall time by stage: $(IFS=,; echo "${stage_times[*]}" | sed 's/,/, /g'); total ${SECONDS} s"

echo "${passed} passed, ${failed} failed"
((failed == 0))
