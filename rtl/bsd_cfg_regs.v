// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Per-pin DIGCFG bits 4:0 and output latches. Pins in FIXED_MASK hold
// FIXED_CFG and ignore configuration writes (their output latch stays writable).
module bsd_cfg_regs #(
    parameter integer               NUM_PINS   = 5,
    parameter [NUM_PINS-1:0]        FIXED_MASK = 0,
    parameter [8*NUM_PINS-1:0]      FIXED_CFG  = 0
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  cfg_we_i,
    input  wire                  out_we_i,
    input  wire [5:0]            pin_idx_i,    // the pin both writes address
    input  wire [4:0]            cfg_wdata_i,
    input  wire                  out_wdata_i,
    output wire [5*NUM_PINS-1:0] cfg_o,        // every pin's DIGCFG bits 4:0
    output wire [NUM_PINS-1:0]   out_o,        // every pin's output latch
    output wire [NUM_PINS-1:0]   oe_o          // every pin's output enable: !IODIR
);
    localparam [4:0] CFG_RESET = 5'b00001;  // input, latch disarmed

    // The addressed pin: two 3-bit decoders and one gate per pin.
    wire [7:0] dec_lo = 8'd1 << pin_idx_i[2:0];
    wire [7:0] dec_hi = 8'd1 << pin_idx_i[5:3];
    // Constant 0 (a lint sink for decoder lines that select no pin).
    /* verilator coverage_off */
    wire       unused_dec = ^{dec_lo, dec_hi};  // lines beyond NUM_PINS - 1
    /* verilator coverage_on */

    genvar p;
    generate
        for (p = 0; p < NUM_PINS; p = p + 1) begin : g_pin
            wire sel = dec_hi[p / 8] && dec_lo[p % 8];
            reg  out_q;
            always @(posedge clk) begin
                if (out_we_i && sel) out_q <= out_wdata_i;
                if (rst) out_q <= 1'b0;
            end
            assign out_o[p] = out_q;

            if (FIXED_MASK[p]) begin : g_fixed
                assign cfg_o[5*p +: 5] = FIXED_CFG[8*p +: 5];
                assign oe_o[p]         = !FIXED_CFG[8*p];
            end else begin : g_free
                // The output enable is IODIR inverted, kept in a flop of its
                // own so that the pad's enable needs no gate per pin.
                reg [4:0] cfg_q;
                reg       oe_q;
                always @(posedge clk) begin
                    if (cfg_we_i && sel) begin
                        cfg_q <= cfg_wdata_i;
                        oe_q  <= !cfg_wdata_i[0];
                    end
                    if (rst) begin
                        cfg_q <= CFG_RESET;
                        oe_q  <= !CFG_RESET[0];
                    end
                end
                assign cfg_o[5*p +: 5] = cfg_q;
                assign oe_o[p]         = oe_q;
            end
        end
    endgenerate

`ifdef FORMAL
`include "bsd_cfg_regs_props.vh"
`endif
endmodule
`default_nettype wire
