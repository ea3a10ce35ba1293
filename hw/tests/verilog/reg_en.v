// n-bit register with load enable: `CostTable::register(n)` (reg_bit per bit).
module reg_en #(parameter N = 16) (
    input              clk,
    input              en,
    input      [N-1:0] d,
    output reg [N-1:0] q
);
    always @(posedge clk)
        if (en) q <= d;
endmodule
