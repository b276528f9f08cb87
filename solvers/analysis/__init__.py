"""Post-processing of solved shapes: curvature measures (circle fits, quadratic surface fits)."""
