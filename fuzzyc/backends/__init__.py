"""Back ends: the C99 float/double header (c/), the fixed-point header (c_fixed/) and the lookup
table (lut)."""
