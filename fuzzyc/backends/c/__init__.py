"""The C99 float/double header: the rule base, its defuzzifiers and signal chain as static inline C, its guard, its proof, its loader."""
