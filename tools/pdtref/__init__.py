"""pdtref: the independent numpy reference of pdtfit's mathematics.

Written from the equations (the paper and the literature it cites), not from
the C code, so that agreement between the two means something. numpy only
(the status codes are read from the C header by pdtsupport.status); scipy
may be used by tools and tests outside this package, never inside it.
"""
