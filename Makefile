# pcdm: parallel constrained Delaunay meshing (Chew, Chrisochoides, Sukup, TR-97-17).
# One non-recursive makefile.  Build output lives in build/ (build/san/ for SANITIZE=1);
# the programs ./mesh ./meshcheck ./pcdm ./pbw are placed at the repository root.
#
#   make            build everything            make test        build and run every test
#   make demo       ./pcdm on 4 ranks           make bench       the paper's tables and more
#   make deps       install Open MPI, Check, METIS  make SANITIZE=1 test   ASan + UBSan build
#   make TSAN=1 test  ThreadSanitizer build (build/tsan), the threaded tests only (tests/run.sh)
#   make DEBUG=1    debug build (build/debug, MESH_ASSERT on)
#   make format     clang-format the tree       make clean
#   make install    programs, libpcdm, libpcdm_seq and libpcdm_threads (.a, .so), include/pcdm.h,
#                   pcdm_par.h, pcdm.pc, pcdm-seq.pc and pcdm-threads.pc into PREFIX
#                   (default /usr/local; DESTDIR for staging)    make uninstall
#   make test-hosts ./pcdm, ./pbw and the runtime across 3 hosts made of network namespaces
#                   (TCP between them; faults, bad set-ups; root only, skips otherwise)
#   make bench-hosts round trips across those hosts (runtime, MPI, TCP), RSR counts
#   make fuzz       libFuzzer run of ./mesh's reader and mesher (FUZZ_TIME seconds, default 90;
#                   clang-14; corpus tests/fuzz/corpus, findings in build/fuzz/artifacts)

CC := mpicc
STD := -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE
WARN := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wpointer-arith \
        -Wformat=2 -Wundef -Wvla -Wno-unused-parameter -Wno-sign-compare
# -ffp-contract=off: the exact predicates rely on every product and sum being rounded once.
OPT := -O2 -g -ffp-contract=off -fno-fast-math
CFLAGS ?=
LDLIBS := -lmetis -lpthread -lm

ifeq ($(SANITIZE),1)
B := build/san
# MESH_DEBUG turns on the debug-only assertion tier (MESH_ASSERT, mesher/base/base.h).
OPT := -O1 -g -ffp-contract=off -fno-omit-frame-pointer -fsanitize=address,undefined \
       -fno-sanitize-recover=undefined -DMESH_DEBUG
LDFLAGS += -fsanitize=address,undefined
export ASAN_OPTIONS := detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS := print_stacktrace=1:halt_on_error=1
else ifeq ($(TSAN),1)
B := build/tsan
# ThreadSanitizer over the threaded pieces (the runtime's workers, ./pcdm --threads).  Open MPI
# is not instrumented: tests/tsan.supp names what TSan reports inside it (and only that).
OPT := -O1 -g -ffp-contract=off -fno-omit-frame-pointer -fsanitize=thread -DMESH_DEBUG
LDFLAGS += -fsanitize=thread
export TSAN_OPTIONS := halt_on_error=1 second_deadlock_stack=1 suppressions=$(CURDIR)/tests/tsan.supp
else ifeq ($(DEBUG),1)
B := build/debug
OPT := -O1 -g -ffp-contract=off -fno-omit-frame-pointer -DMESH_DEBUG
else
B := build
endif

# PCDM_THREADS: pcdm_triangulate has its threaded path (mesher/api/api_thr.c) in this build.
ALL_CFLAGS = $(STD) $(WARN) $(OPT) -DPCDM_THREADS -Iinclude -Iruntime -Imesher $(CFLAGS)
CHECK_CFLAGS = $(shell pkg-config --cflags check 2>/dev/null)
CHECK_LIBS = $(shell pkg-config --libs check 2>/dev/null)

RT_SRC := $(wildcard runtime/*.c)
MESH_SRC := $(wildcard mesher/*/*.c)
# apps/: the programs' mains, and the front end they share (apps/cli.c, apps/cli_tables.c,
# linked into each).
APP_LIB_SRC := $(wildcard apps/cli*.c)
APP_SRC := $(filter-out $(APP_LIB_SRC),$(wildcard apps/*.c))
TEST_SRC := $(wildcard tests/unit_*.c tests/mpi_*.c)
BENCH_SRC := $(wildcard bench/*.c)

RT_LIB := $(B)/libpcdm_rt.a
MESH_LIB := $(B)/libpcdm_mesher.a
APP_LIB := $(B)/libpcdm_apps.a
APPS := $(patsubst apps/%.c,%,$(APP_SRC))
TESTS := $(patsubst tests/%.c,$(B)/tests/%,$(TEST_SRC))
# the tests of libpcdm_threads (tests/thr_*.c): linked with it, no MPI (its rules are below)
THR_TESTS := $(patsubst tests/%.c,$(B)/tests/%,$(wildcard tests/thr_*.c))
BENCHES := $(patsubst bench/%.c,$(B)/bench/%,$(BENCH_SRC))

.PHONY: all libs install uninstall examples deps fuzz fuzz-deps fuzz-replay stress test check-deps demo bench bench-quick bench-seq bench-coast bench-primitives bench-python test-hosts bench-hosts format clean
.DEFAULT_GOAL := all
# Keep the objects of programs and tests (they are intermediate files to make otherwise).
.SECONDARY: $(patsubst %.c,$(B)/obj/%.o,$(APP_SRC) $(TEST_SRC) $(BENCH_SRC))

all: $(patsubst %,$(B)/bin/%,$(APPS)) $(APPS) $(TESTS) $(THR_TESTS) $(BENCHES) libs

# Install what the build needs when it is missing (Debian); does nothing otherwise.
deps:
	@sh tests/deps.sh

$(B)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(CHECK_CFLAGS) -MMD -MP -c $< -o $@

$(RT_LIB): $(patsubst %.c,$(B)/obj/%.o,$(RT_SRC))
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(MESH_LIB): $(patsubst %.c,$(B)/obj/%.o,$(MESH_SRC))
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(APP_LIB): $(patsubst %.c,$(B)/obj/%.o,$(APP_LIB_SRC))
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(B)/bin/%: $(B)/obj/apps/%.o $(APP_LIB) $(MESH_LIB) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $< $(APP_LIB) $(MESH_LIB) $(RT_LIB) $(LDLIBS) -o $@

# Programs live at the root; sanitizer and debug builds keep theirs under $(B)/bin.
ifeq ($(B),build)
$(APPS): %: $(B)/bin/%
	cp $< $@
else
$(APPS): %: $(B)/bin/%
	@true
endif

$(B)/tests/%: $(B)/obj/tests/%.o $(APP_LIB) $(MESH_LIB) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $< $(APP_LIB) $(MESH_LIB) $(RT_LIB) $(CHECK_LIBS) $(LDLIBS) -o $@

$(B)/bench/%: $(B)/obj/bench/%.o $(MESH_LIB) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $< $(MESH_LIB) $(RT_LIB) $(LDLIBS) -o $@

# ---- the library (issue 15): libpcdm.a and libpcdm.so from position-independent objects
# ($(B)/pic), the public header include/pcdm.h (mesher/api implements it), pcdm.pc.
# The version is include/pcdm.h's (PCDM_VERSION_MAJOR/MINOR/PATCH); the soname carries the major.
pcdm_ver = $(shell sed -n 's/^\#define PCDM_VERSION_$(1) *\([0-9]*\).*/\1/p' include/pcdm.h)
PCDM_SOMAJOR := $(call pcdm_ver,MAJOR)
PCDM_VERSION := $(PCDM_SOMAJOR).$(call pcdm_ver,MINOR).$(call pcdm_ver,PATCH)
LIB_SRC := $(RT_SRC) $(MESH_SRC)
PIC_OBJ := $(patsubst %.c,$(B)/pic/%.o,$(LIB_SRC))
LIB_A := $(B)/lib/libpcdm.a
LIB_SO := $(B)/lib/libpcdm.so.$(PCDM_VERSION)
PREFIX ?= /usr/local
DESTDIR ?=
BINDIR = $(PREFIX)/bin
LIBDIR = $(PREFIX)/lib
INCDIR = $(PREFIX)/include
MPI_CFLAGS = $(shell $(CC) -showme:compile 2>/dev/null)
MPI_LIBS = $(shell $(CC) -showme:link 2>/dev/null)

# The sequential library libpcdm_seq (pcdm_triangulate and the validator, include/pcdm.h):
# the sources listed in mesher/seq_sources.txt -- the one list, which the Python build reads
# too -- compiled with the plain C compiler and linked with neither MPI nor METIS.
SEQ_CC ?= cc
SEQ_SRC := $(wildcard $(shell sed 's/\#.*//' mesher/seq_sources.txt))
SEQ_OBJ := $(patsubst %.c,$(B)/seq/%.o,$(SEQ_SRC))
LIB_SEQ_A := $(B)/lib/libpcdm_seq.a
LIB_SEQ_SO := $(B)/lib/libpcdm_seq.so.$(PCDM_VERSION)

$(B)/seq/%.o: %.c
	@mkdir -p $(dir $@)
	$(SEQ_CC) $(STD) $(WARN) $(OPT) -fPIC -Iinclude -Imesher $(CFLAGS) -MMD -MP -c $< -o $@

$(LIB_SEQ_A): $(SEQ_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(LIB_SEQ_SO): $(SEQ_OBJ) mesher/api/pcdm_seq.map
	@mkdir -p $(dir $@)
	$(SEQ_CC) -shared $(LDFLAGS) -Wl,-soname,libpcdm_seq.so.$(PCDM_SOMAJOR) -Wl,--no-undefined \
	    -Wl,--version-script,mesher/api/pcdm_seq.map $(SEQ_OBJ) -lm -o $@

# libpcdm_threads: the sequential interface (include/pcdm.h) with pcdm_options.threads, and no
# MPI: the whole library's sources plus the one-process MPI stand-in runtime/mpi1 (its mpi.h on
# the include path in place of MPI's; no other build names that folder), compiled with the plain
# C compiler and linked with METIS and pthreads only.  Exports what libpcdm_seq exports.
THR_SRC := $(LIB_SRC) runtime/mpi1/mpi1.c
THR_OBJ := $(patsubst %.c,$(B)/thr/%.o,$(THR_SRC))
THR_CFLAGS = $(STD) $(WARN) $(OPT) -fPIC -pthread -DPCDM_THREADS -Iruntime/mpi1 -Iinclude \
             -Iruntime -Imesher $(CFLAGS)
THR_LIBS := -lmetis -lpthread -lm
LIB_THR_A := $(B)/lib/libpcdm_threads.a
LIB_THR_SO := $(B)/lib/libpcdm_threads.so.$(PCDM_VERSION)

$(B)/thr/%.o: %.c
	@mkdir -p $(dir $@)
	$(SEQ_CC) $(THR_CFLAGS) $(CHECK_CFLAGS) -MMD -MP -c $< -o $@

$(LIB_THR_A): $(THR_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

$(LIB_THR_SO): $(THR_OBJ) mesher/api/pcdm_seq.map
	@mkdir -p $(dir $@)
	$(SEQ_CC) -shared $(LDFLAGS) -Wl,-soname,libpcdm_threads.so.$(PCDM_SOMAJOR) -Wl,--no-undefined \
	    -Wl,--version-script,mesher/api/pcdm_seq.map $(THR_OBJ) $(THR_LIBS) -o $@

$(B)/tests/thr_%: $(B)/thr/tests/thr_%.o $(LIB_THR_A)
	@mkdir -p $(dir $@)
	$(SEQ_CC) $(LDFLAGS) $< $(LIB_THR_A) $(CHECK_LIBS) $(THR_LIBS) -o $@

libs: $(LIB_A) $(LIB_SO) $(LIB_SEQ_A) $(LIB_SEQ_SO) $(LIB_THR_A) $(LIB_THR_SO)

$(B)/pic/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -fPIC -MMD -MP -c $< -o $@

$(LIB_A): $(PIC_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && ar rcs $@ $^

# Only the public API is exported (mesher/api/pcdm.map); the layers below stay internal.
$(LIB_SO): $(PIC_OBJ) mesher/api/pcdm.map
	@mkdir -p $(dir $@)
	$(CC) -shared $(LDFLAGS) -Wl,-soname,libpcdm.so.$(PCDM_SOMAJOR) \
	    -Wl,--version-script,mesher/api/pcdm.map $(PIC_OBJ) $(LDLIBS) -o $@

$(B)/pcdm-seq.pc: mesher/api/pcdm-seq.pc.in Makefile
	@mkdir -p $(dir $@)
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(PCDM_VERSION)|' $< > $@

$(B)/pcdm-threads.pc: mesher/api/pcdm-threads.pc.in Makefile
	@mkdir -p $(dir $@)
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(PCDM_VERSION)|' $< > $@

$(B)/pcdm.pc: mesher/api/pcdm.pc.in Makefile
	@mkdir -p $(dir $@)
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(PCDM_VERSION)|' \
	    -e 's|@MPI_CFLAGS@|$(MPI_CFLAGS)|' -e 's|@MPI_LIBS@|$(MPI_LIBS)|' $< > $@

# The .pc file names PREFIX, so it is rebuilt on every install.
install: $(patsubst %,$(B)/bin/%,$(APPS)) libs
	@rm -f $(B)/pcdm.pc $(B)/pcdm-seq.pc $(B)/pcdm-threads.pc && \
	    $(MAKE) --no-print-directory $(B)/pcdm.pc $(B)/pcdm-seq.pc $(B)/pcdm-threads.pc \
	    PREFIX=$(PREFIX)
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCDIR)
	install -m 755 $(patsubst %,$(B)/bin/%,$(APPS)) $(DESTDIR)$(BINDIR)/
	install -m 644 $(LIB_A) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(LIB_SO) $(DESTDIR)$(LIBDIR)/
	ln -sf libpcdm.so.$(PCDM_VERSION) $(DESTDIR)$(LIBDIR)/libpcdm.so.$(PCDM_SOMAJOR)
	ln -sf libpcdm.so.$(PCDM_SOMAJOR) $(DESTDIR)$(LIBDIR)/libpcdm.so
	install -m 644 $(LIB_SEQ_A) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(LIB_SEQ_SO) $(DESTDIR)$(LIBDIR)/
	ln -sf libpcdm_seq.so.$(PCDM_VERSION) $(DESTDIR)$(LIBDIR)/libpcdm_seq.so.$(PCDM_SOMAJOR)
	ln -sf libpcdm_seq.so.$(PCDM_SOMAJOR) $(DESTDIR)$(LIBDIR)/libpcdm_seq.so
	install -m 644 $(LIB_THR_A) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(LIB_THR_SO) $(DESTDIR)$(LIBDIR)/
	ln -sf libpcdm_threads.so.$(PCDM_VERSION) $(DESTDIR)$(LIBDIR)/libpcdm_threads.so.$(PCDM_SOMAJOR)
	ln -sf libpcdm_threads.so.$(PCDM_SOMAJOR) $(DESTDIR)$(LIBDIR)/libpcdm_threads.so
	install -m 644 include/pcdm.h include/pcdm_par.h $(DESTDIR)$(INCDIR)/
	install -m 644 $(B)/pcdm.pc $(B)/pcdm-seq.pc $(B)/pcdm-threads.pc $(DESTDIR)$(LIBDIR)/pkgconfig/

uninstall:
	rm -f $(patsubst %,$(DESTDIR)$(BINDIR)/%,$(APPS)) $(DESTDIR)$(INCDIR)/pcdm.h \
	    $(DESTDIR)$(INCDIR)/pcdm_par.h \
	    $(DESTDIR)$(LIBDIR)/libpcdm.a $(DESTDIR)$(LIBDIR)/libpcdm.so \
	    $(DESTDIR)$(LIBDIR)/libpcdm.so.$(PCDM_SOMAJOR) $(DESTDIR)$(LIBDIR)/libpcdm.so.$(PCDM_VERSION) \
	    $(DESTDIR)$(LIBDIR)/libpcdm_seq.a $(DESTDIR)$(LIBDIR)/libpcdm_seq.so \
	    $(DESTDIR)$(LIBDIR)/libpcdm_seq.so.$(PCDM_SOMAJOR) \
	    $(DESTDIR)$(LIBDIR)/libpcdm_seq.so.$(PCDM_VERSION) \
	    $(DESTDIR)$(LIBDIR)/libpcdm_threads.a $(DESTDIR)$(LIBDIR)/libpcdm_threads.so \
	    $(DESTDIR)$(LIBDIR)/libpcdm_threads.so.$(PCDM_SOMAJOR) \
	    $(DESTDIR)$(LIBDIR)/libpcdm_threads.so.$(PCDM_VERSION) \
	    $(DESTDIR)$(LIBDIR)/pkgconfig/pcdm.pc $(DESTDIR)$(LIBDIR)/pkgconfig/pcdm-seq.pc \
	    $(DESTDIR)$(LIBDIR)/pkgconfig/pcdm-threads.pc

test: deps
	@$(MAKE) --no-print-directory all
	@BUILD=$(B) SANITIZE=$(SANITIZE) TSAN=$(TSAN) bash tests/run.sh

# Three hosts on this machine (network namespaces, TCP between them); needs root, else skips.
test-hosts: deps
	@$(MAKE) --no-print-directory all
	@B=$(B) bash tests/hosts/run.sh

bench-hosts: deps
	@$(MAKE) --no-print-directory all
	@B=$(B) bash bench/hosts.sh

demo: deps
	@$(MAKE) --no-print-directory all
	@bash bench/demo.sh

bench: deps
	@$(MAKE) --no-print-directory all
	@bash bench/bench.sh

bench-quick: deps
	@$(MAKE) --no-print-directory all
	@QUICK=1 bash bench/bench.sh

bench-seq: deps
	@$(MAKE) --no-print-directory all
	@bash bench/seq.sh

# The parallel meshers on real coastlines at 10M triangles, by phase (also a section of make bench).
bench-coast: deps
	@$(MAKE) --no-print-directory all
	@bash bench/coast_scale.sh

# The Python section alone (bench/python.py; the package installed by tests/t_python.sh).
bench-python: deps
	@$(MAKE) --no-print-directory all
	@B=$(B) bash tests/t_python.sh >/dev/null
	@$(B)/pyvenv/bin/python bench/python.py $(if $(QUICK),--sizes 1e6 --reps 1,)

bench-primitives: deps
	@$(MAKE) --no-print-directory all
	@B=$(B) bash bench/primitives.sh

CLANG_FORMAT ?= $(shell command -v clang-format || command -v clang-format-14)
format:
	$(CLANG_FORMAT) -i $(wildcard runtime/*.[ch] runtime/mpi1/*.[ch] mesher/*/*.[ch] apps/*.[ch] tests/*.[ch] tests/fuzz/*.c bench/*.c include/*.h examples/*.[ch])

# ---- fuzzing (issue 10): clang's libFuzzer with ASan + UBSan over the reader and the mesher.
# The seed corpus lives in git (tests/fuzz/corpus); the run works on a copy in build/fuzz, so
# the tree is never written; crashes, timeouts and leaks land in build/fuzz/artifacts (copy
# each one into tests/fuzz/regress with its expected outcome, tests/t_fuzz_regress.sh).
FUZZ_CC ?= clang-14
FUZZ_TIME ?= 90
# FUZZ_SEED and FUZZ_RUNS make a run repeatable (CI: a fixed seed and a fixed number of inputs,
# so CI explores the same inputs every time and a red CI is a real, reproducible finding).
FUZZ_SEED ?= 0
FUZZ_RUNS ?= -1
FUZZ_FLAGS := -g -O1 -ffp-contract=off -fno-omit-frame-pointer \
              -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -DMESH_DEBUG
# The sequential library's sources (mesher/seq_sources.txt: the sequential layers, the validator
# and the driver's sequential stages; no MPI).
FUZZ_SRC := $(SEQ_SRC)
build/fuzz/fuzz_mesh: tests/fuzz/fuzz_mesh.c $(FUZZ_SRC) $(wildcard mesher/*/*.h)
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(STD) $(FUZZ_FLAGS) -Iinclude -Imesher $< $(FUZZ_SRC) -lm -o $@

fuzz-deps:
	@FUZZ=1 sh tests/deps.sh

fuzz: fuzz-deps
	@$(MAKE) --no-print-directory build/fuzz/fuzz_mesh
	@mkdir -p build/fuzz/corpus build/fuzz/artifacts
	cp -n tests/fuzz/corpus/* build/fuzz/corpus/ 2>/dev/null || true
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	    build/fuzz/fuzz_mesh -max_total_time=$(FUZZ_TIME) -runs=$(FUZZ_RUNS) -seed=$(FUZZ_SEED) \
	    -timeout=20 -rss_limit_mb=2048 \
	    -max_len=8192 -print_final_stats=1 \
	    -artifact_prefix=build/fuzz/artifacts/ -dict=tests/fuzz/poly.dict build/fuzz/corpus

# The fuzz corpus (the in-tree seeds and whatever make fuzz added in build/fuzz/corpus) replayed
# through ./pcdm and ./pbw against ./mesh's answer (tests/fuzz/replay_par.sh; not in make test).
fuzz-replay: deps
	@$(MAKE) --no-print-directory all
	@bash tests/fuzz/replay_par.sh tests/fuzz/corpus $(wildcard build/fuzz/corpus)

# the schedule explorer: ./pbw and ./pcdm at 2-8 ranks under many message schedules, every mesh
# checked; a fixed sample of 400 runs in at most 5 minutes unless STRESS_RUNS, STRESS_TIME,
# STRESS_SEED say otherwise (tests/stress.sh); failures are kept in build/stress
stress: deps
	@$(MAKE) --no-print-directory all
	@bash tests/stress.sh

clean:
	rm -rf build $(APPS)

-include $(shell find build -name '*.d' 2>/dev/null)
