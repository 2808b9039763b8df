"""pdtsupport: what pdtfit's Python tools and tests share that is not the
reference's mathematics: the deterministic random generators (rng), the
plant simulator (plant), the monitor's closed-loop records (loop), the
`pdtfit` program and its helpers for tests (cli), and the library's status
codes read from its C header (status), and the commit and machine a
generated report names (provenance)."""
