"""The C99 float/double header: the rule base, its defuzzifiers and signal chain as static inline
C (header), its last gate (guard), its run-time-error proof (proof) and its loader (load)."""
