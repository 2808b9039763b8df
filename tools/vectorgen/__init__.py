"""Generators of the C test vectors; see tools/gen_vectors.py."""
