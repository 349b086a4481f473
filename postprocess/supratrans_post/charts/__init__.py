"""The speed/accuracy charts: `stability` (largest stable dt against c, next to the paper's condition) and
`work_precision` (error against wall time and dt, ours against the SciPy peer, and the equal-error table)."""
