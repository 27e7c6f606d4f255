// SPDX-License-Identifier: Apache-2.0
// The waveform writer of the standalone harnesses (session.cpp, virtual.cpp): FST or VCD as
// the build chose (make's TRACE), or, in an untraced build (the benchmark's), a stand-in
// that is never opened.
#pragma once

#if VM_TRACE_FST
#include "verilated_fst_c.h"
using Trace = VerilatedFstC;
#elif VM_TRACE
#include "verilated_vcd_c.h"
using Trace = VerilatedVcdC;
#else
#include <cstdint>
struct Trace {
    void open(const char*) {}
    void dump(uint64_t) {}
    void close() {}
};
#endif
