"""The pcdm package's C extension (pyproject.toml holds the rest).

The sources are the sequential library's -- the list mesher/seq_sources.txt, which the
Makefile reads too (libpcdm_seq) -- plus the programs' front end (apps/cli.c,
apps/cli_tables.c: the switch parser) and python/pcdm/_core.c.  No MPI.  The version is
include/pcdm.h's.  The flags are the Makefile's that matter for correctness: C11, and no
contraction of products into fused multiply-adds (the exact predicates need every product
and sum rounded once).
"""

import glob
import os
import re

import numpy
from setuptools import Extension, setup

ROOT = os.path.dirname(os.path.abspath(__file__))


def rel(p):
    return os.path.relpath(os.path.join(ROOT, p), os.getcwd())


def version():
    text = open(os.path.join(ROOT, "include", "pcdm.h")).read()
    v = [re.search(r"#define PCDM_VERSION_%s\s+(\d+)" % k, text).group(1)
         for k in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(v)


def seq_sources():
    out = []
    for line in open(os.path.join(ROOT, "mesher", "seq_sources.txt")):
        pat = line.split("#", 1)[0].strip()
        if pat:
            hits = sorted(glob.glob(os.path.join(ROOT, pat)))
            if not hits:
                raise SystemExit("mesher/seq_sources.txt: %s names no file" % pat)
            out += [os.path.relpath(h, ROOT) for h in hits]
    return out


sources = ["python/pcdm/_core.c", "apps/cli.c", "apps/cli_tables.c"] + seq_sources()

ext = Extension(
    "pcdm._core",
    sources=[rel(s) for s in sources],
    include_dirs=[rel("include"), rel("mesher"), rel("apps"), numpy.get_include()],
    define_macros=[("_POSIX_C_SOURCE", "200809L"), ("_DEFAULT_SOURCE", None)],
    extra_compile_args=["-std=c11", "-O2", "-ffp-contract=off", "-fno-fast-math",
                        "-Wno-unused-parameter", "-Wno-sign-compare"],
    libraries=["m"],
)

# build/python: beside the Makefile's build output, not over it; every object rebuilt (setuptools
# does not see a changed header, and pip builds in the tree)
setup(version=version(), ext_modules=[ext],
      options={"build": {"build_base": os.path.join("build", "python")},
               "build_ext": {"force": True}})
