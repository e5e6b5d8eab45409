"""The fixed-point (q15/q31) header: integer arithmetic from raw inputs to outputs, for boards
without an FPU (header: the rule base; chain: the signal chain)."""
