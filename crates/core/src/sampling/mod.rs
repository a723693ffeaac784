//! Layer 1: random numbers, samplers, warps from the unit square with their pdfs and
//! inverses, 1-D distributions, MIS heuristics, and the chi-square harness.
