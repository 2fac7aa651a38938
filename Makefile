# xdyna build. `make` builds bin/xdyna; `make check` installs what is missing
# and runs the tests; see README.md for the other targets.

PRECISION ?= double
FC := mpif90
PY := /usr/bin/python3

# HDF5's Fortran API (Debian's serial build): include and library paths
H5SHOW := $(shell h5fc -shlib -show 2>/dev/null)
H5INC := $(filter -I%,$(H5SHOW))
H5LIB := $(filter -L%,$(H5SHOW)) -lhdf5_fortran -lhdf5
LIBS := $(H5LIB) -llapack -lblas -lmetis

ifeq ($(PRECISION),single)
  PFLAGS := -DXD_SINGLE
  SUFFIX := _single
else
  PFLAGS :=
  SUFFIX :=
endif

COMMON := -cpp -fopenmp -ffree-line-length-132 -std=f2018 -fall-intrinsics -Wall -Wno-maybe-uninitialized \
          -Wno-unused-dummy-argument -Wno-surprising $(PFLAGS) $(H5INC)
# one binary for every node of a cluster: x86-64-v3 (AVX2, FMA: every x86-64
# server CPU since 2015, Intel and AMD); `make NATIVE=1` for the host's own
# instruction set (results may then differ in round-off from one CPU to another)
# (its objects in build/release*_native, so that switching rebuilds)
ifeq ($(NATIVE),1)
  ARCH := native
  RTAG := $(SUFFIX)_native
else
  ARCH := x86-64-v3
  RTAG := $(SUFFIX)
endif
# -fno-tree-loop-distribute-patterns: short copy and zeroing loops stay
# loops instead of calls to memcpy and memset (a shell block's gathers of 64
# values were a call each: 6% of the shell plate's run in perf; the plate
# and car6 3% faster, the same results bit for bit)
RELEASE_FLAGS := -O3 -g -march=$(ARCH) -funroll-loops -fstack-arrays -fno-tree-loop-distribute-patterns $(COMMON)
DEBUG_FLAGS := -O0 -g -fcheck=all,no-array-temps -ffpe-trap=invalid,zero,overflow -finit-real=snan -finit-integer=-77777 \
               -fbacktrace $(COMMON)

SRC := $(shell find src -name '*.f90' -o -name '*.F90' | grep -v '^src/main/' | sort)
MAIN := src/main/xdyna.f90
TEST_SRC := $(sort $(wildcard tests/unit/test_*.f90))

flat = $(subst /,_,$(patsubst src/%,%,$(patsubst tests/%,tests_%,$(basename $(1))))).o

.PHONY: all deps check demo bench bench-mpi debug clean verify tests examples stability sweeps contact-suite public car6-designs fuzz
all: bin/xdyna$(SUFFIX) bin/thdiff

deps:
	@sh tools/deps.sh

# compile rules and module dependencies, generated from the sources
ALL_SRC := $(SRC) $(MAIN) $(TEST_SRC) tests/unit/testing.f90 tests/unit/fixtures.f90 bench/global_search_bench.f90
build/rules$(RTAG).mk: $(ALL_SRC) tools/mkrules.sh
	@mkdir -p build
	@sh tools/mkrules.sh "build/release$(RTAG):RELEASE_FLAGS build/debug$(SUFFIX):DEBUG_FLAGS" $(ALL_SRC) > $@

-include build/rules$(RTAG).mk

R_OBJ := $(addprefix build/release$(RTAG)/,$(foreach f,$(SRC),$(call flat,$(f))))
D_OBJ := $(addprefix build/debug$(SUFFIX)/,$(foreach f,$(SRC),$(call flat,$(f))))

bin/xdyna$(SUFFIX): $(R_OBJ) build/release$(RTAG)/$(call flat,$(MAIN))
	@mkdir -p bin
	$(FC) -fopenmp -o $@ $^ $(LIBS)

bin/xdyna_debug$(SUFFIX): $(D_OBJ) build/debug$(SUFFIX)/$(call flat,$(MAIN))
	@mkdir -p bin
	$(FC) -fopenmp -g -o $@ $^ $(LIBS)

bin/search_bench$(SUFFIX): $(R_OBJ) build/release$(RTAG)/bench_global_search_bench.o
	@mkdir -p bin
	$(FC) -fopenmp -o $@ $^ $(LIBS)

bin/thdiff: src/tools/thdiff.py
	@mkdir -p bin
	cp $< $@
	chmod +x $@

TEST_BIN := $(patsubst tests/unit/%.f90,build/tests$(SUFFIX)/%,$(TEST_SRC))
build/tests$(SUFFIX)/%: build/debug$(SUFFIX)/tests_unit_%.o build/debug$(SUFFIX)/tests_unit_testing.o build/debug$(SUFFIX)/tests_unit_fixtures.o $(D_OBJ)
	@mkdir -p $(@D)
	$(FC) -fopenmp -g -o $@ $^ $(LIBS)

tests: $(TEST_BIN)

debug: deps
	@$(MAKE) --no-print-directory bin/xdyna_debug$(SUFFIX)

# the suite on every core (CHECK_JOBS=1: one at a time); tests/README.md
CHECK_JOBS ?= $(shell nproc)

check: deps
	@sh tools/deps.sh check || echo "deps: python3-vtk9 could not be installed; the d3plot reader test will SKIP"
	@$(MAKE) --no-print-directory all tests bin/xdyna_debug$(SUFFIX)
	@$(PY) -m pytest -q -n $(CHECK_JOBS) --dist loadgroup

demo: deps
	@$(MAKE) --no-print-directory all
	@rm -rf out/demo && mkdir -p out/demo
	./bin/xdyna i=input_decks/contact/tube_crush.k outdir=out/demo h5plot=1
	@$(PY) tools/xdplot.py mesh out/demo --color plastic_strain --out out/demo/tube_crush_states.png
	@$(PY) tools/xdplot.py history out/demo --out out/demo/tube_crush_histories.png
	@echo "demo: a square tube crushed into folds with automatic contact; log d3hsp, time histories"
	@echo "(glstat, matsum, nodout, rcforc, thist.h5), states (the d3plot family for LS-PrePost and"
	@echo "other LS-DYNA readers; d3plot.h5 + d3plot.xdmf for ParaView and the pictures)"
	@echo "and pictures (tube_crush_states.png, tube_crush_histories.png) are in out/demo/"

# the paper's three examples (section 7) with the search knobs: runs in
# out/examples/, pictures in doc/examples/, tables in doc/examples.md
examples: deps
	@$(MAKE) --no-print-directory all
	@$(PY) tools/examples.py

verify: deps
	@$(MAKE) --no-print-directory all
	@XDYNA_BIN=$(CURDIR)/bin/xdyna$(SUFFIX) $(PY) tools/verify.py

sweeps: deps
	@$(MAKE) --no-print-directory all
	@$(MAKE) --no-print-directory PRECISION=single bin/xdyna_single
	@$(PY) tools/sweeps.py

contact-suite: deps
	@$(MAKE) --no-print-directory all
	@$(PY) tools/contact_suite.py

stability: deps
	@$(MAKE) --no-print-directory all
	@$(PY) tools/stability.py

public: deps
	@$(MAKE) --no-print-directory all
	@$(PY) tools/public_decks.py

car6-designs: deps
	@$(MAKE) --no-print-directory all
	@$(PY) tools/car6_designs.py

fuzz: deps
	@$(MAKE) --no-print-directory all
	@$(PY) tools/fuzz.py --seconds $${FUZZ_SECONDS:-600}

bench: deps
	@$(MAKE) --no-print-directory all bin/search_bench$(SUFFIX)
	@$(MAKE) --no-print-directory PRECISION=single bin/xdyna_single
	@sh bench/run_bench.sh

# the tubes array on 1, 2, 4 MPI ranks: memory per rank, halo bytes, MPI
# phases (bench/run_bench_mpi.sh; BENCH_MPI_TUBES, _CYCLES, _RANKS)
bench-mpi: deps
	@$(MAKE) --no-print-directory all
	@sh bench/run_bench_mpi.sh

clean:
	rm -rf build bin out
