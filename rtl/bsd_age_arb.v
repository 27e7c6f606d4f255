`default_nettype none
// Grants the oldest requester. A request is "born" on the clock it rises;
// requesters born on the same clock rank by index (lowest first). Keeps an
// age matrix: older_q[j*K+i] = requester j is older than requester i.
// The grant is combinational and already counts this clock's newborns.
module bsd_age_arb #(
    parameter integer K = 4
) (
    input  wire         clk,
    input  wire         rst,
    input  wire [K-1:0] req_i,
    input  wire [K-1:0] exclude_i,  // pending but not eligible (being served)
    output reg  [K-1:0] gnt_o       // one-hot or zero
);
    reg  [K-1:0]   req_q;
    reg  [K*K-1:0] older_q;
    reg  [K*K-1:0] older_d;
    wire [K-1:0]   born = req_i & ~req_q;
    wire [K-1:0]   cand = req_i & ~exclude_i;

    integer i, j;
    always @* begin
        for (j = 0; j < K; j = j + 1) begin
            for (i = 0; i < K; i = i + 1) begin
                if (born[i])
                    older_d[j*K+i] = req_q[j] || (born[j] && j < i);
                else if (born[j])
                    older_d[j*K+i] = 1'b0;
                else
                    older_d[j*K+i] = older_q[j*K+i];
            end
        end
        for (i = 0; i < K; i = i + 1) begin
            gnt_o[i] = cand[i];
            for (j = 0; j < K; j = j + 1)
                if (j != i && cand[j] && older_d[j*K+i]) gnt_o[i] = 1'b0;
        end
    end

    always @(posedge clk) begin
        req_q   <= req_i;
        older_q <= older_d;
        if (rst) begin
            req_q   <= {K{1'b0}};
            older_q <= {K*K{1'b0}};
        end
    end
endmodule
`default_nettype wire
