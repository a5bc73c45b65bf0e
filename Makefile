# pcdm: parallel constrained Delaunay meshing (Chew, Chrisochoides, Sukup, TR-97-17).
# One non-recursive makefile.  Build output lives in build/ (build/san/ for SANITIZE=1);
# the programs ./mesh ./meshcheck ./pcdm ./pbw are placed at the repository root.
#
#   make            build everything            make test        build and run every test
#   make demo       ./pcdm on 4 ranks           make bench       the paper's tables and more
#   make deps       install Open MPI, Check, METIS  make SANITIZE=1 test   ASan + UBSan build
#   make DEBUG=1    debug build (build/debug, MESH_ASSERT on)
#   make format     clang-format the tree       make clean

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
else ifeq ($(DEBUG),1)
B := build/debug
OPT := -O1 -g -ffp-contract=off -fno-omit-frame-pointer -DMESH_DEBUG
else
B := build
endif

ALL_CFLAGS = $(STD) $(WARN) $(OPT) -Iruntime -Imesher $(CFLAGS)
CHECK_CFLAGS = $(shell pkg-config --cflags check 2>/dev/null)
CHECK_LIBS = $(shell pkg-config --libs check 2>/dev/null)

RT_SRC := $(wildcard runtime/*.c)
MESH_SRC := $(wildcard mesher/*/*.c)
APP_SRC := $(wildcard apps/*.c)
TEST_SRC := $(wildcard tests/unit_*.c tests/mpi_*.c)
BENCH_SRC := $(wildcard bench/*.c)

RT_LIB := $(B)/libpcdm_rt.a
MESH_LIB := $(B)/libpcdm_mesher.a
APPS := $(patsubst apps/%.c,%,$(APP_SRC))
TESTS := $(patsubst tests/%.c,$(B)/tests/%,$(TEST_SRC))
BENCHES := $(patsubst bench/%.c,$(B)/bench/%,$(BENCH_SRC))

.PHONY: all deps test check-deps demo bench bench-quick bench-seq bench-primitives format clean
.DEFAULT_GOAL := all
# Keep the objects of programs and tests (they are intermediate files to make otherwise).
.SECONDARY: $(patsubst %.c,$(B)/obj/%.o,$(APP_SRC) $(TEST_SRC) $(BENCH_SRC))

all: $(patsubst %,$(B)/bin/%,$(APPS)) $(APPS) $(TESTS) $(BENCHES)

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

$(B)/bin/%: $(B)/obj/apps/%.o $(MESH_LIB) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $< $(MESH_LIB) $(RT_LIB) $(LDLIBS) -o $@

# Programs live at the root; sanitizer and debug builds keep theirs under $(B)/bin.
ifeq ($(B),build)
$(APPS): %: $(B)/bin/%
	cp $< $@
else
$(APPS): %: $(B)/bin/%
	@true
endif

$(B)/tests/%: $(B)/obj/tests/%.o $(MESH_LIB) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $< $(MESH_LIB) $(RT_LIB) $(CHECK_LIBS) $(LDLIBS) -o $@

$(B)/bench/%: $(B)/obj/bench/%.o $(MESH_LIB) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $< $(MESH_LIB) $(RT_LIB) $(LDLIBS) -o $@

test: deps
	@$(MAKE) --no-print-directory all
	@BUILD=$(B) SANITIZE=$(SANITIZE) bash tests/run.sh

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

bench-primitives: deps
	@$(MAKE) --no-print-directory all
	@B=$(B) bash bench/primitives.sh

CLANG_FORMAT ?= $(shell command -v clang-format || command -v clang-format-14)
format:
	$(CLANG_FORMAT) -i $(wildcard runtime/*.[ch] mesher/*/*.[ch] apps/*.c tests/*.[ch] bench/*.c)

clean:
	rm -rf build $(APPS)

-include $(shell find build -name '*.d' 2>/dev/null)
