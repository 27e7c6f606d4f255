#!/bin/sh
# The `regression` target of brainstem_dio.core: the repository's own regression, `make test`
# (Verilator lint, then the cocotb/pytest tests on Verilator and Icarus), run in the core's
# checkout: FuseSoC sets FILES_ROOT to the folder of the .core file when it runs a script.
# From a checkout without FuseSoC: FILES_ROOT=. sh tb/fusesoc/regression.sh
set -e
: "${FILES_ROOT:?FILES_ROOT is not set (FuseSoC sets it to the core's folder)}"
echo "regression: make test in $FILES_ROOT"
exec make -C "$FILES_ROOT" test
