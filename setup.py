"""The pcdm package's C extensions (pyproject.toml holds the rest).

pcdm._core: the sequential library's sources -- the list mesher/seq_sources.txt, which the
Makefile reads too (libpcdm_seq) -- plus the programs' front end (apps/cli.c,
apps/cli_tables.c: the switch parser) and python/pcdm/_core.c.  No MPI.  Where METIS is found
(metis.h and libmetis), the whole library instead, as the Makefile builds libpcdm_threads: every
.c of runtime/ and mesher/*/ plus runtime/mpi1/mpi1.c, the one-process MPI stand-in, whose mpi.h
comes first on the include path -- pcdm_triangulate then takes threads >= 1 (./pcdm's subdomain
mesher on worker threads) with METIS and pthreads and still no MPI; without METIS it refuses
threads (ValueError).  PCDM_THREADS=0: never; PCDM_THREADS=1: required, an error otherwise.

pcdm._par (pcdm.parallel, for mpi4py users): the whole library -- the Makefile's library
sources, every .c of runtime/ and mesher/*/ -- and python/pcdm/_par.c, with MPI's flags (from
mpicc) and METIS.  Built when mpicc is on PATH and metis.h is found (PCDM_MPI=0: never;
PCDM_MPI=1: required, an error otherwise); pcdm and pcdm._core never load MPI.

pcdm/data: the project's example domains, data/*.poly, copied in when the package is built
(pcdm.get_data's own examples).

The version is include/pcdm.h's.  The flags are the Makefile's that matter for correctness:
C11, and no contraction of products into fused multiply-adds (the exact predicates need every
product and sum rounded once).
"""

import glob
import os
import re
import shutil
import subprocess
import sysconfig

import copy

import numpy
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

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


def lib_sources():
    """The whole library's sources (the Makefile's LIB_SRC): runtime/*.c and mesher/*/*.c."""
    lib = sorted(glob.glob(os.path.join(ROOT, "runtime", "*.c")) +
                 glob.glob(os.path.join(ROOT, "mesher", "*", "*.c")))
    return [os.path.relpath(f, ROOT) for f in lib]


def metis_missing(extra_incs=()):
    """None when metis.h and libmetis are found, else what is missing."""
    incs = [os.path.dirname(sysconfig.get_paths()["include"]), "/usr/include",
            "/usr/local/include"] + list(extra_incs) + \
        [d for d in os.environ.get("CPATH", "").split(":") if d]
    if not any(os.path.exists(os.path.join(d, "metis.h")) for d in incs):
        return "no metis.h (libmetis-dev)"
    libdirs = ["/usr/lib", "/usr/local/lib", "/usr/lib64", sysconfig.get_config_var("LIBDIR") or ""] + \
        glob.glob("/usr/lib/*-linux-gnu") + \
        [d for d in os.environ.get("LIBRARY_PATH", "").split(":") if d]
    if not any(glob.glob(os.path.join(d, "libmetis.*")) for d in libdirs if d):
        return "no libmetis"
    return None


def core_threaded():
    """True: pcdm._core with the threaded path (PCDM_THREADS=1 makes a missing METIS an error)."""
    want = os.environ.get("PCDM_THREADS", "")
    if want == "0":
        return False
    why = metis_missing()
    if why:
        if want == "1":
            raise SystemExit("PCDM_THREADS=1: cannot build the threaded path: " + why)
        print("pcdm: building pcdm.triangulate without threads: " + why)
        return False
    return True


THREADED = core_threaded()
front = ["python/pcdm/_core.c", "apps/cli.c", "apps/cli_tables.c"]
if THREADED:
    sources = front + lib_sources() + ["runtime/mpi1/mpi1.c"]
else:
    sources = front + seq_sources()

CFLAGS = ["-std=c11", "-O2", "-ffp-contract=off", "-fno-fast-math", "-Wno-unused-parameter",
          "-Wno-sign-compare"]
MACROS = [("_POSIX_C_SOURCE", "200809L"), ("_DEFAULT_SOURCE", None)]

ext = Extension(
    "pcdm._core",
    sources=[rel(s) for s in sources],
    include_dirs=([rel("runtime/mpi1")] if THREADED else []) +
    [rel("include"), rel("mesher"), rel("apps"), numpy.get_include()] +
    ([rel("runtime")] if THREADED else []),
    define_macros=MACROS + ([("PCDM_THREADS", None)] if THREADED else []),
    extra_compile_args=CFLAGS + (["-pthread"] if THREADED else []),
    extra_link_args=["-pthread"] if THREADED else [],
    libraries=(["metis", "pthread"] if THREADED else []) + ["m"],
)


def mpi_extension():
    """pcdm._par, or None (PCDM_MPI=1 makes a missing MPI or METIS an error)."""
    want = os.environ.get("PCDM_MPI", "")
    if want == "0":
        return None
    why = None
    mpicc = shutil.which("mpicc")
    if not mpicc:
        why = "no mpicc on PATH"
    else:
        try:
            comp = subprocess.run([mpicc, "-showme:compile"], capture_output=True, text=True,
                                  check=True).stdout.split()
            link = subprocess.run([mpicc, "-showme:link"], capture_output=True, text=True,
                                  check=True).stdout.split()
        except (OSError, subprocess.CalledProcessError):  # MPICH and others: -show
            out = subprocess.run([mpicc, "-show"], capture_output=True, text=True).stdout.split()
            comp = [a for a in out[1:] if a.startswith(("-I", "-D"))]
            link = [a for a in out[1:] if a.startswith(("-L", "-l", "-Wl"))]
        why = metis_missing([a[2:] for a in comp if a.startswith("-I")])
    if why:
        if want == "1":
            raise SystemExit("PCDM_MPI=1: cannot build pcdm._par: " + why)
        print("pcdm: building without pcdm.parallel: " + why)
        return None
    srcs = ["python/pcdm/_par.c"] + lib_sources()
    return Extension(
        "pcdm._par",
        sources=[rel(s) for s in srcs],
        include_dirs=[rel("include"), rel("mesher"), rel("runtime"), numpy.get_include()] +
        [a[2:] for a in comp if a.startswith("-I")],
        define_macros=MACROS + [("PCDM_THREADS", None)],
        extra_compile_args=CFLAGS + [a for a in comp if not a.startswith("-I")],
        library_dirs=[a[2:] for a in link if a.startswith("-L")],
        libraries=["metis", "pthread", "m"] + [a[2:] for a in link if a.startswith("-l")],
        extra_link_args=[a for a in link if a.startswith("-Wl")],
    )


exts = [ext] + [e for e in [mpi_extension()] if e]

# build/python: beside the Makefile's build output, not over it; every object rebuilt (setuptools
# does not see a changed header, and pip builds in the tree), and the staging folders of an
# earlier build emptied first (a module built then, e.g. pcdm._par before PCDM_MPI=0, would
# otherwise ride along into the wheel)
for d in glob.glob(os.path.join(ROOT, "build", "python", "lib*")) + \
        glob.glob(os.path.join(ROOT, "build", "python", "bdist*")):
    shutil.rmtree(d, ignore_errors=True)


class BuildExt(build_ext):
    """Each extension's objects in a folder of its own: pcdm._core and pcdm._par compile the
    same sources against different mpi.h (runtime/mpi1's, MPI's), so one folder would hand
    one's objects to the other.  A shallow copy of the command per extension keeps this safe
    when the extensions build at once (build_ext's parallel option)."""

    def build_extension(self, ext):
        mine = copy.copy(self)
        mine.build_temp = os.path.join(self.build_temp, ext.name)
        return build_ext.build_extension(mine, ext)


class BuildPy(build_py):
    """The package's own example domains, data/*.poly (the project's, MIT), as pcdm/data, where
    pcdm.get_data finds them."""

    def run(self):
        build_py.run(self)
        out = os.path.join(self.build_lib, "pcdm", "data")
        os.makedirs(out, exist_ok=True)
        for f in sorted(glob.glob(os.path.join(ROOT, "data", "*.poly"))):
            self.copy_file(f, os.path.join(out, os.path.basename(f)))


setup(version=version(), ext_modules=exts, cmdclass={"build_ext": BuildExt, "build_py": BuildPy},
      options={"build": {"build_base": os.path.join("build", "python")},
               "build_ext": {"force": True, "parallel": os.cpu_count() or 1}})
