// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Synchronous FIFO with AXI-Stream-style ports. DEPTH words (a power of two)
// sit in a RAM with a registered read, which maps onto one iCE40 block RAM
// (512 x 8) or any FPGA's; one more word sits in the RAM's read register.
// With SKID = 1 a skid register behind it holds another (DEPTH + 2 words),
// so that the RAM's read enable comes from flops only and m_axis_tready
// (a consumer's long pick logic) reaches only the two output valid flags.
// With SKID = 0 there is no skid, whose WIDTH flops and output mux a wide
// word would pay for, and m_axis_tready reaches the read enable: for a
// consumer whose tready is a flop (bsd_drain below 17 timers; from 17 a
// gate on a flop and the head's timer bit) or a gate on flops and a
// registered ready (bsd_pkt_tx behind the host link's register slice).
// s_axis_tready and m_axis_tvalid come from flops either way.
//
// Latency: a word written into an empty FIFO is offered 2 clocks later.
// The RAM is never read and written at the same address on one clock (a read
// needs a word in the RAM, a write needs a free slot), so the RAM's
// read-during-write behaviour does not matter.
module bsd_fifo #(
    parameter integer WIDTH = 8,
    parameter integer DEPTH = 16,
    parameter integer SKID  = 1
) (
    input  wire             clk,
    input  wire             rst,
    input  wire [WIDTH-1:0] s_axis_tdata,
    input  wire             s_axis_tvalid,
    output wire             s_axis_tready,
    output wire [WIDTH-1:0] m_axis_tdata,
    output wire             m_axis_tvalid,
    input  wire             m_axis_tready,
    output wire             empty_o        // nothing stored, output register included
);
    localparam integer AW = $clog2(DEPTH);

`ifndef SYNTHESIS
    initial begin
        if (DEPTH < 2 || (1 << AW) != DEPTH)
            $fatal(1, "bsd_fifo: DEPTH = %0d must be a power of two, at least 2", DEPTH);
        if (AW > 16)  // the pointers' LFSR taps (below) go to 16 bits
            $fatal(1, "bsd_fifo: DEPTH = %0d is above 65536", DEPTH);
    end
`endif

    // The RAM's words hold only what passes the ports, whose toggles are
    // counted there (s_axis_tdata, out_data_q); Verilator counts an array's
    // bits only below 256 of them, so a small queue's words would count the
    // same data again, with the bits a build keeps constant. Outside coverage.
    /* verilator coverage_off */
    (* no_rw_check *)  // never read and written at one address on one clock (below)
    reg [WIDTH-1:0] mem [0:DEPTH-1];
    /* verilator coverage_on */
    // No wrap bit above the addresses: full and empty are flops of their own,
    // so equal pointers never need telling apart.
    reg [AW-1:0]    wr_q;
    reg [AW-1:0]    rd_q;
    // The RAM's read register, and the skid register that takes its word when
    // a read comes while the output waits. The skid holds the older word, so
    // it is offered first; it is only ever full beside a full read register.
    reg [WIDTH-1:0] out_data_q;
    reg             out_valid_q;
    reg [WIDTH-1:0] skid_data_q;
    reg             skid_valid_q;
    wire            skid_valid = SKID != 0 && skid_valid_q;

    assign m_axis_tdata  = skid_valid ? skid_data_q : out_data_q;
    assign m_axis_tvalid = out_valid_q;

    // Full and empty as flops, so that push and pop (the RAM's enables) do
    // not wait for pointer comparators; the comparators work out the next
    // clock's flags from the current pointers instead.
    reg  ram_empty_q;
    reg  ram_full_q;
    wire push      = s_axis_tvalid && !ram_full_q;
    wire take      = out_valid_q && m_axis_tready;
    // With a skid: a read whenever the skid is free (the read register's word
    // then either leaves now or moves to the skid). Without: whenever the
    // read register is free or its word leaves now.
    wire pop       = !ram_empty_q && (SKID != 0 ? !skid_valid_q : (!out_valid_q || m_axis_tready));
    // The pointers step through the DEPTH addresses in a fixed order, not by
    // + 1: a shift register whose new bit is the XOR of two (or four) of its
    // bits, a maximal LFSR, with the all-zero state spliced into its cycle
    // (the new bit also flips when the bits below the top are all 0), so
    // that it visits every address. A step is a gate or two, not an
    // incrementer (iCE40: a LUT per bit); both pointers walk the same order,
    // which is all a queue needs.
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function [15:0] taps(input integer w);
        case (w)
            1:       taps = 16'h1;
            2:       taps = 16'h3;
            3:       taps = 16'h5;
            4:       taps = 16'h9;
            5:       taps = 16'h12;
            6:       taps = 16'h21;
            7:       taps = 16'h41;
            8:       taps = 16'h8E;
            9:       taps = 16'h108;
            10:      taps = 16'h204;
            11:      taps = 16'h402;
            12:      taps = 16'h829;
            13:      taps = 16'h1013;
            14:      taps = 16'h2803;
            15:      taps = 16'h4001;
            default: taps = 16'h8805;
        endcase
    endfunction
    /* verilator coverage_on */
    localparam [15:0]   TAPS_16 = taps(AW);
    localparam [AW-1:0] TAPS = TAPS_16[AW-1:0];
    localparam [AW-1:0] LOW  = {AW{1'b1}} >> 1;  // the bits below the top
    function [AW-1:0] step(input [AW-1:0] p);
        /* verilator lint_off UNUSEDSIGNAL */
        reg [AW:0] s;  // p and the new bit; the top bit shifts out
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            s    = {p, ^(p & TAPS) ^ ((p & LOW) == {AW{1'b0}})};
            step = s[AW-1:0];
        end
    endfunction

    assign s_axis_tready = !ram_full_q;
    assign empty_o       = ram_empty_q && !out_valid_q;

    // RAM ports: no reset, so they map onto block RAM.
    always @(posedge clk) begin
        if (push) mem[wr_q] <= s_axis_tdata;
    end

    always @(posedge clk) begin
        if (pop) out_data_q <= mem[rd_q];
    end

    always @(posedge clk) begin
        // One word from empty / full: a lone pop empties, a lone push fills
        // (a push never meets a full RAM, nor a pop an empty one). The full
        // flag's next value does not wait for push (s_axis_tvalid, a long
        // path in the top): push only enables it.
        if (push || pop) begin
            ram_full_q  <= !pop && step(wr_q) == rd_q;
            ram_empty_q <= !push && step(rd_q) == wr_q;
        end
        // (the steps called here, under their enables: a simulator works
        // them out only on a clock that moves a pointer; after the flags, which
        // read the pointers, so that a simulator keeps no copy of them)
        if (push) wr_q <= step(wr_q);
        if (pop) rd_q <= step(rd_q);
        if (!skid_valid) skid_data_q <= out_data_q;  // kept only when skid_valid rises
        if (skid_valid) begin
            if (m_axis_tready) skid_valid_q <= 1'b0;
        end else if (pop && out_valid_q && !m_axis_tready) begin
            skid_valid_q <= SKID != 0;
        end
        // (the clear, then the pop that overrides it: out_valid_q is read before it is written)
        if (take && !skid_valid) out_valid_q <= 1'b0;
        if (pop) out_valid_q <= 1'b1;
        if (rst) begin
            wr_q        <= {AW{1'b0}};
            rd_q        <= {AW{1'b0}};
            ram_empty_q <= 1'b1;
            ram_full_q  <= 1'b0;
            out_valid_q <= 1'b0;
            skid_valid_q <= 1'b0;
        end
    end

`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block; the formal props assert it
    // The invariant above, checked: a read and a write of one RAM address on one clock
    // would make the RAM's read-during-write behaviour matter.
    // Nested under the write, so an idle clock costs the simulation one test.
    always @(posedge clk) begin
        if (push) begin
            if (pop && !rst && wr_q == rd_q)
                $fatal(1, "bsd_fifo: RAM read and write of address %0d on one clock", rd_q);
        end
    end
`endif
`endif

`ifdef FORMAL
`include "bsd_fifo_props.vh"
`endif
endmodule
`default_nettype wire
