// A loadable table of E x W bits in flip-flops: one write port, one asynchronous read port
// (`CostTable::table` with `tables: FlopRam`, flop_ram_bit per bit; the write decoder is not
// in the model).
module ram_flop #(parameter A = 6, parameter W = 8) (
    input              clk,
    input              we,
    input      [A-1:0] waddr,
    input      [W-1:0] wdata,
    input      [A-1:0] raddr,
    output     [W-1:0] rdata
);
    reg [W-1:0] mem [0:(1<<A)-1];
    always @(posedge clk)
        if (we) mem[waddr] <= wdata;
    assign rdata = mem[raddr];
endmodule
