// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// RFLX strobes: every clock, the waiting value with the lowest device ID is
// strobed on rflx_*_o (registered), and its source is told at once. Timer
// device IDs rise with the pin, so the lowest waiting timer is the lowest pin.
module bsd_rflx_arb #(
    parameter integer NUM_PINS      = 5,
    parameter integer TIMER_ID_BASE = 10
) (
    input  wire                   clk,
    input  wire                   rst,
    input  wire                   dio_req_i,
    input  wire [5:0]             dio_id_i,
    input  wire                   dio_val_i,
    input  wire [NUM_PINS-1:0]    dio_below_i,   // dio_id_i < the timer ID of pin p
    output wire                   dio_done_o,
    input  wire [NUM_PINS-1:0]    timer_req_i,
    input  wire [16*NUM_PINS-1:0] timer_result_i,
    output wire [NUM_PINS-1:0]    timer_done_o,
    output wire                   rflx_valid_o,
    output wire [5:0]             rflx_id_o,
    output wire [15:0]            rflx_data_o
);
    // The lowest waiting timer (lowest pin).
    reg                t_any;
    reg [5:0]          t_id;
    reg [15:0]         t_result;
    reg [NUM_PINS-1:0] t_onehot;
    integer p;
    always @* begin
        t_any    = 1'b0;
        t_id     = 6'd0;
        t_result = 16'd0;
        t_onehot = {NUM_PINS{1'b0}};
        for (p = NUM_PINS - 1; p >= 0; p = p - 1) begin
            if (timer_req_i[p]) begin
                t_any    = 1'b1;
                t_id     = TIMER_ID_BASE[5:0] + p[5:0];
                t_result = timer_result_i[16*p +: 16];
                t_onehot = {NUM_PINS{1'b0}};
                t_onehot[p] = 1'b1;
            end
        end
    end

    // The DIG_IO value goes first when it ranks below the lowest waiting timer,
    // i.e. below every waiting timer (timer IDs rise with the pin), which
    // needs no priority chain.
    wire pick_dio = dio_req_i && !(|(timer_req_i & ~dio_below_i));
    assign dio_done_o = pick_dio;
    assign timer_done_o = t_onehot & ~({NUM_PINS{dio_req_i}} & dio_below_i);

    reg        rflx_valid_q;
    reg [5:0]  rflx_id_q;
    reg [15:0] rflx_data_q;

    assign rflx_valid_o = rflx_valid_q;
    assign rflx_id_o    = rflx_id_q;
    assign rflx_data_o  = rflx_data_q;

    always @(posedge clk) begin
        rflx_valid_q <= pick_dio || t_any;
        rflx_id_q    <= pick_dio ? dio_id_i : t_id;
        rflx_data_q  <= pick_dio ? {15'd0, dio_val_i} : t_result;
        if (rst) begin
            rflx_valid_q <= 1'b0;
            rflx_id_q    <= 6'd0;
            rflx_data_q  <= 16'd0;
        end
    end

`ifdef FORMAL
`include "bsd_rflx_arb_props.vh"
`endif
endmodule
`default_nettype wire
