#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# The `regression` target of brainstem_dio.core: the repository's own regression, `make test`
# (Verilator lint, FuseSoC check, then the cocotb/pytest tests on Verilator and Icarus), run in
# the core's checkout. FuseSoC sets FILES_ROOT (relative to its work folder) to the sources it
# uses: with `fusesoc run --no-export --target regression ...` that is the checkout itself;
# without --no-export it is a copy of the listed files only, where there is no regression to run.
# From a checkout without FuseSoC: FILES_ROOT=. sh tb/fusesoc/regression.sh
set -e
: "${FILES_ROOT:?FILES_ROOT is not set (FuseSoC sets it to the core's folder)}"
if [ ! -f "$FILES_ROOT/Makefile" ] || [ ! -d "$FILES_ROOT/tb/lib" ]; then
    echo "regression: $FILES_ROOT is FuseSoC's copy of the listed files, not the checkout:" >&2
    echo "regression: run  fusesoc run --no-export --target regression brainstem:dio:brainstem_dio" >&2
    exit 1
fi
echo "regression: make test in $FILES_ROOT"
exec make -C "$FILES_ROOT" test
