"""The rosbridge v2 ops, one module per op family (rosbridge_suite's `capabilities/`). Each module
exports OPS: op name -> Op; app/rosbridge/ops.py gathers them."""
