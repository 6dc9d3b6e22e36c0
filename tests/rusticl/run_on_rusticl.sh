#!/usr/bin/env bash
# Runs one test program with Mesa's rusticl on llvmpipe as the selected device (ctest label
# `rusticl`, docs/devices.md): RUSTICL_ENABLE=llvmpipe, MSMCL_DEVICE=llvmpipe, strict
# selection. Usage: run_on_rusticl.sh MSMCL_CLI TEST_PROGRAM [ARGS...]
# No rusticl device: skipped (exit 77), or a failure when MSMCL_REQUIRE_RUSTICL=1 (CI).
# A driver warning on stderr ("MESA: warning") fails the run. Mesa's disk shader cache is off:
# llvmpipe warns while it compiles a kernel, and a cached kernel would hide the warning.
set -u
export RUSTICL_ENABLE=llvmpipe MSMCL_DEVICE=llvmpipe MSMCL_STRICT=1 MESA_SHADER_CACHE_DISABLE=true
cli=$1
shift
if ! "$cli" devices 2>/dev/null | grep -q "platform rusticl"; then
    if [ "${MSMCL_REQUIRE_RUSTICL:-0}" = 1 ]; then
        echo "no rusticl device (RUSTICL_ENABLE=llvmpipe; install mesa-opencl-icd) and MSMCL_REQUIRE_RUSTICL=1"
        exit 1
    fi
    echo "no rusticl device: skipped"
    exit 77
fi
errors=$(mktemp)
trap 'rm -f "$errors"' EXIT
"$@" 2>"$errors"
status=$?
cat "$errors" >&2
# Any driver warning fails: no kernel prints one (docs/devices.md).
if grep -q "MESA: warning" "$errors"; then
    echo "driver warnings on stderr (above)"
    exit 1
fi
exit $status
