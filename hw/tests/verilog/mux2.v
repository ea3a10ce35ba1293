// n-bit 2:1 multiplexer: `CostTable::mux(n, 2)`.
module mux2 #(parameter N = 16) (
    input          sel,
    input  [N-1:0] a,
    input  [N-1:0] b,
    output [N-1:0] y
);
    assign y = sel ? b : a;
endmodule
