// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// brainstem_dio on a serial line: bsd_uart_rx -> RX FIFO -> brainstem_dio ->
// (cmdQOverflow merge) -> bsd_uart_tx, with the heartbeat on as the original
// module (HB_RATE 10 = 256 ms). Everything else is the core's contract.
//
// RX FIFO: bytes that arrive while the core holds its input (a reply still
// waiting for the slower serial output) are kept, FIFO_DEPTH + 4 of them
// (the RAM, the FIFO's read and skid registers, the register slice in front of the core).
// A byte that finds the FIFO full is dropped (rx_overflow pulses) and the
// message cmdQOverflow `A, 2, 0x80, 12` is sent, once per overflow burst:
// a burst starts with a dropped byte and ends when the FIFO has emptied.
// The message goes out at the next packet boundary of the core's output
// (never inside a packet), ahead of a core packet waiting at that boundary.
// A host that waits for each reply before it sends the next command never
// has more than one packet (at most 10 bytes) in the FIFO.
module brainstem_dio_uart #(
    parameter integer               CLK_HZ        = 48_000_000,
    parameter integer               BAUD          = 9600,
    parameter integer               FIFO_DEPTH    = 512,
    parameter integer               MODULE_ADDR   = 2,
    parameter integer               NUM_PINS      = 5,
    parameter [NUM_PINS-1:0]        TIMER_MASK    = 5'b11110,
    parameter [NUM_PINS-1:0]        FIXED_MASK    = 0,
    parameter [8*NUM_PINS-1:0]      FIXED_CFG     = 0,
    parameter integer               PIN_ID_BASE   = 5,
    parameter integer               TIMER_ID_BASE = 10,
    parameter integer               TRANS_ID_BASE = 15,
    parameter integer               POLL_HZ       = 10_000,
    parameter integer               RX_TIMEOUT_US = 25_600,
    parameter integer               HB_RATE       = 10
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                rx,           // host -> module serial line (idle high)
    output wire                tx,           // module -> host serial line
    input  wire [NUM_PINS-1:0] pin_i,
    output wire [NUM_PINS-1:0] pin_o,
    output wire [NUM_PINS-1:0] pin_oe,
    output wire [NUM_PINS-1:0] raw_trans,
    output wire                rflx_valid,
    output wire [5:0]          rflx_id,
    output wire [15:0]         rflx_data,
    output wire                link_up,
    output wire                frame_err,    // one-clock strobe: a byte with a bad stop bit was dropped
    output wire                rx_overflow   // one-clock strobe (a clock late): a byte was dropped, FIFO full
);
    `include "bsd_protocol.vh"

    // ------------------------------------------------------------ receive
    wire [7:0] rx_data;
    wire       rx_valid;

    bsd_uart_rx #(.CLK_HZ(CLK_HZ), .BAUD(BAUD)) u_rx (
        .clk         (clk),
        .rst         (rst),
        .rx_i        (rx),
        .data_o      (rx_data),
        .valid_o     (rx_valid),
        .frame_err_o (frame_err)
    );

    wire       fifo_ready;
    wire       fifo_empty;
    wire [7:0] fifo_tdata;
    wire       fifo_tvalid, fifo_tready;

    bsd_fifo #(.WIDTH(8), .DEPTH(FIFO_DEPTH)) u_fifo (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tdata  (rx_data),
        .s_axis_tvalid (rx_valid),
        .s_axis_tready (fifo_ready),
        .m_axis_tdata  (fifo_tdata),
        .m_axis_tvalid (fifo_tvalid),
        .m_axis_tready (fifo_tready),
        .empty_o       (fifo_empty)
    );

    // A register slice between the FIFO and the core, so that the core's
    // s_axis_tready (the parser's state and the executor's hold) drives only
    // the slice's enables, not the FIFO's block-RAM read.
    // It holds one more byte, so the input keeps FIFO_DEPTH + 4 in all.
    wire [7:0] core_s_tdata;
    wire       core_s_tvalid, core_s_tready;

    bsd_axis_skid #(.WIDTH(8)) u_in_slice (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tdata  (fifo_tdata),
        .s_axis_tvalid (fifo_tvalid),
        .s_axis_tready (fifo_tready),
        .m_axis_tdata  (core_s_tdata),
        .m_axis_tvalid (core_s_tvalid),
        .m_axis_tready (core_s_tready)
    );

    // The serial line cannot wait: a byte the FIFO cannot take is lost.
    wire drop = rx_valid && !fifo_ready;

    reg  rx_overflow_q;
    reg  burst_q;     // in an overflow burst (until the FIFO has emptied)
    reg  ovf_pend_q;  // cmdQOverflow waits to be sent
    wire ovf_done;

    assign rx_overflow = rx_overflow_q;

    always @(posedge clk) begin
        rx_overflow_q <= drop;
        if (drop) burst_q <= 1'b1;
        else if (fifo_empty) burst_q <= 1'b0;
        if (ovf_done) ovf_pend_q <= 1'b0;
        // A new burst while the previous message still waits needs no second one.
        if (drop && !burst_q) ovf_pend_q <= 1'b1;
        if (rst) begin
            rx_overflow_q <= 1'b0;
            burst_q       <= 1'b0;
            ovf_pend_q    <= 1'b0;
        end
    end

    // ------------------------------------------------------------ the core
    wire [7:0] core_m_tdata;
    wire       core_m_tvalid, core_m_tready, core_m_tlast;

    brainstem_dio #(
        .CLK_HZ        (CLK_HZ),
        .MODULE_ADDR   (MODULE_ADDR),
        .NUM_PINS      (NUM_PINS),
        .TIMER_MASK    (TIMER_MASK),
        .FIXED_MASK    (FIXED_MASK),
        .FIXED_CFG     (FIXED_CFG),
        .PIN_ID_BASE   (PIN_ID_BASE),
        .TIMER_ID_BASE (TIMER_ID_BASE),
        .TRANS_ID_BASE (TRANS_ID_BASE),
        .POLL_HZ       (POLL_HZ),
        .RX_TIMEOUT_US (RX_TIMEOUT_US),
        .HB_RATE       (HB_RATE)
    ) u_core (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tdata  (core_s_tdata),
        .s_axis_tvalid (core_s_tvalid),
        .s_axis_tready (core_s_tready),
        .m_axis_tdata  (core_m_tdata),
        .m_axis_tvalid (core_m_tvalid),
        .m_axis_tready (core_m_tready),
        .m_axis_tlast  (core_m_tlast),
        .pin_i         (pin_i),
        .pin_o         (pin_o),
        .pin_oe        (pin_oe),
        .raw_trans     (raw_trans),
        .rflx_valid    (rflx_valid),
        .rflx_id       (rflx_id),
        .rflx_data     (rflx_data),
        .link_up       (link_up)
    );

    // ------------------------------------------------------------ transmit
    // A register slice between the core and the merge, so that the merge's
    // and the UART's handshake logic and the core's output logic are never
    // one combinational path (it keeps the board top's Fmax up).
    wire [7:0] out_tdata;
    wire       out_tvalid, out_tready, out_tlast;

    bsd_axis_skid #(.WIDTH(9)) u_out_slice (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tdata  ({core_m_tlast, core_m_tdata}),
        .s_axis_tvalid (core_m_tvalid),
        .s_axis_tready (core_m_tready),
        .m_axis_tdata  ({out_tlast, out_tdata}),
        .m_axis_tvalid (out_tvalid),
        .m_axis_tready (out_tready)
    );

    wire [7:0] mrg_tdata;
    wire       mrg_tvalid, mrg_tready;
    wire       mrg_tlast;

    bsd_msg_merge #(.MODULE_ADDR(MODULE_ADDR), .CODE(MSG_CMD_Q_OVERFLOW)) u_merge (
        .clk           (clk),
        .rst           (rst),
        .req_i         (ovf_pend_q),
        .done_o        (ovf_done),
        .s_axis_tdata  (out_tdata),
        .s_axis_tvalid (out_tvalid),
        .s_axis_tready (out_tready),
        .s_axis_tlast  (out_tlast),
        .m_axis_tdata  (mrg_tdata),
        .m_axis_tvalid (mrg_tvalid),
        .m_axis_tready (mrg_tready),
        .m_axis_tlast  (mrg_tlast)
    );

    // Packet boundaries matter only to the merge; the line carries bytes.
    wire unused_mrg_tlast = mrg_tlast;

    // And one more slice, so the merge's choice does not reach into the
    // UART's shift register in the same clock.
    wire [7:0] tx_tdata;
    wire       tx_tvalid, tx_tready;

    bsd_axis_skid #(.WIDTH(8)) u_tx_slice (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tdata  (mrg_tdata),
        .s_axis_tvalid (mrg_tvalid),
        .s_axis_tready (mrg_tready),
        .m_axis_tdata  (tx_tdata),
        .m_axis_tvalid (tx_tvalid),
        .m_axis_tready (tx_tready)
    );

    bsd_uart_tx #(.CLK_HZ(CLK_HZ), .BAUD(BAUD)) u_tx (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tdata  (tx_tdata),
        .s_axis_tvalid (tx_tvalid),
        .s_axis_tready (tx_tready),
        .tx_o          (tx)
    );
endmodule
`default_nettype wire
