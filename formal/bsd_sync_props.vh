// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_sync (included at the end of the module under `ifdef FORMAL).
// No reset (by design: it carries levels), so the flops start from any value. From the
// second clock on, q_o is d_i of exactly two clocks earlier (the first flop is d_i of one
// clock earlier from the first clock on); q_o is compared with a register of past inputs,
// so it cannot depend on d_i of the same clock (no combinational path). The first clock's
// q_o is the flop's own start value: any value (the "reset value" of a reset-less flop).
    reg             f_past_valid = 1'b0;
    reg             f_past2 = 1'b0;
    reg [WIDTH-1:0] f_d1_q, f_d2_q;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_past2      <= f_past_valid;
        f_d1_q       <= d_i;
        f_d2_q       <= f_d1_q;
    end

    always @(*) begin
        if (f_past_valid) assert(meta_q == f_d1_q);
        if (f_past2) assert(q_o == f_d2_q);
    end

    // Covers: the output differs from the input of the same clock (no path); a rise of the
    // whole word seen two clocks late.
    always @(*) if (f_past2) begin
        cover(q_o != d_i);
        cover(q_o == {WIDTH{1'b1}} && f_d1_q == {WIDTH{1'b0}} && d_i == {WIDTH{1'b0}});
    end
