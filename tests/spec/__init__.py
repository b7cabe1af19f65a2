"""Pure-Python reference implementations: the executable spec of every C
algorithm in csrc/, written to be read next to the weighing and magnetometer
papers.  One module per area (chain, tcomp, image, effects, ...); tests hold
the C against them."""
