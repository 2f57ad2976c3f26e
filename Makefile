# MBSPH build. `make` builds build/mbsph; `make test` runs every test;
# `make run` runs the default case and draws its pictures. See README.md.
ifeq ($(origin FC),default)
FC        = mpif90
endif
HDF5_INC  ?= /usr/include/hdf5/openmpi
HDF5_LIB  ?= /usr/lib/x86_64-linux-gnu/hdf5/openmpi
# FFTW 3: its Fortran interface fftw3.f03 is included by src/wave_fftw.f90 only
FFTW_INC  ?= /usr/include
FFTW_LIB  ?= /usr/lib/x86_64-linux-gnu
# ARCH: -march=native here; `make PORTABLE=1` for a cluster build whose
# login and compute nodes differ.
ifdef PORTABLE
ARCH      ?= -mtune=generic
else
ARCH      ?= -march=native
endif
WARN      = -std=f2008 -Wall -Wextra -fimplicit-none
# -flto: the pair loops call the grid's small functions (grid_ranges) and the
# step the integrators' loops across modules; link-time optimisation inlines
# them (4 % on both bench cases, doc/performance.md)
# no inlining of a function called once: link-time optimisation otherwise inlines the pair
# list's builder into the step, 1.2x slower on the breakwater (doc/performance.md)
OPT_release = -O3 $(ARCH) -flto=auto -fno-inline-functions-called-once
OPT_debug   = -g -O0 -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace
PYTHON    = .venv/bin/python
# the specialised pair loops share one interface; each variant leaves the
# arguments of the models it does not use untouched, by design
XFLAGS_fluid_forces = -Wno-unused-dummy-argument
XFLAGS_wave_fftw = -I$(FFTW_INC)
LIBS      = -L$(HDF5_LIB) -lhdf5_fortran -lhdf5 -L$(FFTW_LIB) -lfftw3

# every object is built twice: build/ (release) and build/debug/
SRC       := $(sort $(wildcard src/*.f90 src/*.F90))
NAMES     := $(basename $(notdir $(SRC)))
LIBNAMES  := $(filter-out mbsph,$(NAMES))
UNIT_SRC  := $(sort $(wildcard tests/unit/test_*.f90))
UNIT      := $(basename $(notdir $(UNIT_SRC)))

.PHONY: all debug deps test wave-heights unit unit-debug unit-3d run dambreak breakwater breakwater_core porous_waves lint bench bench-mpi bench-effects clean figures paper stability study porous damage
all: build/mbsph
debug: build/debug/mbsph

define variant # $(1)=build dir, $(2)=flags
$(1)/obj/%.o: src/%.f90 | $(1)/obj $(1)/mod
	$$(FC) $(2) -I$$(HDF5_INC) -Isrc -J$(1)/mod $$(XFLAGS_$$*) -c $$< -o $$@
$(1)/obj/%.o: src/%.F90 | $(1)/obj $(1)/mod
	$$(FC) $(2) -I$$(HDF5_INC) -Isrc -Ibuild/gen -J$(1)/mod $$(XFLAGS_$$*) -c $$< -o $$@
$(1)/obj/fluid_forces.o: $(GEN)
$(1)/obj/kernel_correction.o: $(GEN)
$(1)/obj/bc_mdbc.o: $(GEN)
$(1)/obj/particles.o: $(GEN)
$(1)/obj/nbr_list.o: $(GEN)
$(1)/obj/contact.o: $(GEN)
$(1)/mbsph: $(addprefix $(1)/obj/,$(addsuffix .o,$(NAMES)))
	$$(FC) $(2) -o $$@ $$^ $$(LIBS)
$(1)/obj/testing.o: tests/unit/testing.f90 | $(1)/obj $(1)/mod
	$$(FC) $(2) -J$(1)/mod -c $$< -o $$@
$(1)/tests/%: tests/unit/%.f90 $(1)/obj/testing.o $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) | $(1)/tests
	$$(FC) $(2) -I$(1)/mod -J$(1)/tests -o $$@ $$< $(1)/obj/testing.o \
	  $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) $$(LIBS)
$(1)/jonswap_signal: tools/jonswap_signal.f90 $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) | $(1)/tests
	$$(FC) $(2) -I$(1)/mod -J$(1)/tests -o $$@ $$< $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) $$(LIBS)
$(1)/deps.mk: $(SRC) tools/fdeps.sh | $(1)/obj
	tools/fdeps.sh $(1)/obj $(SRC) > $$@
$(1)/obj $(1)/mod $(1)/tests:
	mkdir -p $$@
endef
# code generated from a list (fypp, installed by make deps): the pair-loop variants
FYPP := .venv/bin/fypp
# the space dimensions are set in one place, src/constants.f90 (ndim); the generated code takes them from there
NDIM := $(shell sed -n 's/^ *integer, parameter :: ndim = \([0-9]\) .*/\1/p' src/constants.f90)
FYPP_RUN := $(FYPP) -DNDIM=$(NDIM)
GEN  := build/gen/fluid_variants.inc build/gen/fluid_dispatch.inc build/gen/pre_pairs.inc build/gen/pre_decl.inc \
        build/gen/mdbc_ghosts.inc build/gen/nbr_pairs.inc build/gen/shepard_pairs.inc build/gen/contact_pairs.inc \
        build/gen/particle_decl.inc build/gen/particle_table.inc build/gen/particle_slots.inc
build/gen/fluid_variants.inc: src/fluid_variants.fypp src/components.fypp src/fluid_pairs.inc src/fluid_pair_body.inc src/stencil.fypp \
                              | build/gen $(FYPP)
	$(FYPP_RUN) -DPART="'loops'" $< $@
build/gen/fluid_dispatch.inc: src/fluid_variants.fypp src/components.fypp | build/gen $(FYPP)
	$(FYPP_RUN) -DPART="'dispatch'" $< $@
build/gen/pre_pairs.inc: src/pre_pairs.fypp src/components.fypp | build/gen $(FYPP)
	$(FYPP_RUN) -DPART="'body'" $< $@
build/gen/pre_decl.inc: src/pre_pairs.fypp src/components.fypp | build/gen $(FYPP)
	$(FYPP_RUN) -DPART="'decl'" $< $@
build/gen/mdbc_ghosts.inc: src/mdbc_ghosts.fypp src/components.fypp | build/gen $(FYPP)
	$(FYPP_RUN) $< $@
# the passes over the one traversal of pairs, src/stencil.fypp
build/gen/nbr_pairs.inc build/gen/shepard_pairs.inc build/gen/contact_pairs.inc: build/gen/%.inc: src/%.fypp \
                                                                                src/stencil.fypp | build/gen $(FYPP)
	$(FYPP_RUN) $< $@
build/gen/particle_%.inc: src/particle_fields.fypp | build/gen $(FYPP)
	$(FYPP_RUN) -DPART="'$*'" $< $@
$(GEN): src/constants.f90
$(FYPP):
	@bash tools/deps.sh
build/gen:
	mkdir -p $@

$(eval $(call variant,build,$(WARN) $(OPT_release)))
$(eval $(call variant,build/debug,$(WARN) $(OPT_debug)))
-include build/deps.mk build/debug/deps.mk

deps:
	@bash tools/deps.sh

# the tools written against the solver's modules are built with the unit tests, so that they keep compiling
unit: build/mbsph build/jonswap_signal $(addprefix build/tests/,$(UNIT))
	@fail=0; for t in $(UNIT); do build/tests/$$t || fail=1; done; exit $$fail
unit-debug: build/debug/mbsph $(addprefix build/debug/tests/,$(UNIT)) unit-3d
	@fail=0; for t in $(UNIT); do build/debug/tests/$$t || fail=1; done; exit $$fail

# the 3D forms of the dimension-generic modules (rigid, tensor), run in a 3D build of them:
# constants with ndim = 3 (generated from src/constants.f90), the modules as they are, their
# tests (test_tensor as it is; tests/unit3d/test_rigid3d for the 3D rigid body), debug checks on
T3D_MODS := src/kinds.f90 build/t3d/constants.f90 src/tensor.f90 src/rigid.f90 tests/unit/testing.f90
build/t3d/constants.f90: src/constants.f90
	mkdir -p build/t3d
	sed 's/integer, parameter :: ndim = 2 /integer, parameter :: ndim = 3 /' $< > $@
	grep -q 'ndim = 3 ' $@
build/t3d/test_%: $(T3D_MODS) tests/unit3d/test_%.f90
	cd build/t3d && $(FC) $(WARN) $(OPT_debug) -J. $(addprefix $(CURDIR)/,$^) -o $(notdir $@)
build/t3d/test_tensor: $(T3D_MODS) tests/unit/test_tensor.f90
	cd build/t3d && $(FC) $(WARN) $(OPT_debug) -J. $(addprefix $(CURDIR)/,$^) -o $(notdir $@)
unit-3d: build/t3d/test_tensor build/t3d/test_rigid3d
	@fail=0; for t in $^; do $$t || fail=1; done; exit $$fail

# the whole suite: unit tests on the release and the debug build, then the
# integration tests (cases, restart, bad input, output, ParaView, wave heights) on
# TEST_JOBS pytest workers (pytest-xdist; default: the number of cores). The long
# wave-height runs come first (tests/conftest.py); --maxschedchunk=1 makes xdist deal
# them out one per worker instead of giving one worker a block of them all.
TEST_JOBS ?= $(shell nproc)
test: deps
	$(MAKE) -j2 build/mbsph build/debug/mbsph
	$(MAKE) unit unit-debug
	$(PYTHON) -m pytest -q -n $(TEST_JOBS) --maxschedchunk=1 tests

# all four wave-height flumes, with the line each prints (doc/waves.md); 1.7e9 particle-steps, most of the time of make test
wave-heights: deps build/mbsph
	$(PYTHON) -m pytest -q -rA -n $(TEST_JOBS) --maxschedchunk=1 tests/test_waves.py -k height_2_to_4

# mpirun as root (containers, CI) needs these flags; elsewhere they are harmless
MPIRUN    ?= mpirun $(if $(filter 0,$(shell id -u)),--allow-run-as-root) --oversubscribe
RANKS     ?= 2

# the default scene: regular waves on a small breakwater with cube armour (doc/breakwater.md)
run: deps build/mbsph
	$(MPIRUN) -np $(RANKS) build/mbsph input/demo_breakwater.nml
	$(PYTHON) -m post.plot_field OUT/demo_breakwater --field velocity --times 2.0 3.5 5.0 6.0
	$(PYTHON) -m post.armour OUT/demo_breakwater --out OUT/demo_breakwater

# the dam break of the foundation (Martin and Moyce), with its comparison
dambreak: deps build/mbsph
	build/mbsph input/dambreak.nml
	$(PYTHON) -m post.plot_field OUT/dambreak --field pressure
	$(PYTHON) -m post.dambreak OUT/dambreak

# the coarse breakwater with regular and irregular armour placement, each on an
# impermeable and on a porous core: a settling run in still water (1 s), continued under
# waves by a restart; armour figures and the table of the four against the laboratory
# ranges (doc/breakwater.md); cost measured there.
# BW_T0: start of the window in which the wave height is measured at gauge 3 (Ns);
# BW_DOC: where the figures (BW_DOC/img) and the table go. A short trial lowers BW_END
# and BW_T0 and writes elsewhere than doc/: BW_END=3 BW_T0=1.5 BW_DOC=OUT/breakwater_trial.
BW_END ?= 12.0
BW_T0  ?= 5
BW_DOC ?= doc
BW_CASES := regular irregular regular_porous irregular_porous
breakwater: deps build/mbsph
	@for pl in $(BW_CASES); do \
	  echo "== settling: $$pl"; \
	  $(MPIRUN) -np $(RANKS) build/mbsph input/breakwater/$$pl.nml > /dev/null || exit 1; \
	  sed -e "s/t_end = 1.0/t_end = $(BW_END)/" -e "s/overwrite = .true./restart = .true./" \
	    input/breakwater/$$pl.nml > OUT/breakwater_$$pl/waves.nml; \
	  echo "== waves: $$pl (restart of the settled layer until t = $(BW_END) s)"; \
	  $(MPIRUN) -np $(RANKS) build/mbsph OUT/breakwater_$$pl/waves.nml > /dev/null || exit 1; \
	  $(PYTHON) -m post.armour OUT/breakwater_$$pl --gauge 3 --t-start $(BW_T0) --out $(BW_DOC)/img/breakwater_$$pl || exit 1; \
	done
	$(PYTHON) -m post.armour $(foreach c,$(BW_CASES),OUT/breakwater_$(c)) --gauge 3 --t-start $(BW_T0) \
	  --table $(BW_DOC)/breakwater_table.md --out $(BW_DOC)/img

# damage under test series like a laboratory's (doc/damage.md): SERIES names a series file
# (study/series/*.toml): the settling run, then steps of irregular waves of rising Hs,
# each a restart of the last; per step the incident Hm0 and H2% at the toe, Ns and the
# units displaced, into <out>/series.csv and series.png. The default is the short trial
# (three steps of a few waves, under 10 minutes on 2 cores); a finished step is kept.
SERIES ?= study/series/trial.toml
damage: deps build/mbsph
	$(PYTHON) -m post.series $(SERIES)

lint: deps
	bash tools/lint.sh

# the seed paper's cases TC1a, TC1b, TC2, TC3 with every contact model, and their
# figures (doc/img/paper_*.png); TC4 (in water) with `make paper`
PAPER_FIG := $(foreach c,tc1a_rolling tc1b_sliding tc2_jump tc3_receding,$(foreach m,dynamic repulsive noncohesive noncohesive_spring hertz,$(c)_$(m)))
figures: deps build/mbsph
	@for c in $(PAPER_FIG); do echo "== $$c"; build/mbsph input/paper/$$c.nml > /dev/null || exit 1; done
	$(PYTHON) -m post.paper_cases OUT/paper --out doc/img

paper: figures
	@for m in dynamic repulsive noncohesive noncohesive_spring hertz; do build/mbsph input/paper/tc4_stack_$$m.nml > /dev/null || exit 1; done

# hard cases, long runs (about 15 minutes on one core); each case's exit status is kept
# beside its output (a case may be meant to stop), the verdicts go to doc/stability.md
stability: deps build/mbsph
	@for c in input/stability/*.nml; do n=$$(basename $$c .nml); echo "== $$c"; mkdir -p OUT/stability/$$n; \
	  build/mbsph $$c > /dev/null 2> OUT/stability/$$n/stderr; echo $$? > OUT/stability/$$n/exit_status; done
	$(PYTHON) -m post.stability OUT/stability/* --table doc/stability.md

# accuracy against cost: every study of study/*.toml (resumable: finished runs are
# kept in OUT/study/), its tables into doc/accuracy-cost.md, its figures into doc/img;
# cost = CPU time of each run, which other processes do not inflate;
# `make study STUDIES=study/tank_dp.toml` for one, STUDY_FLAGS="--workers 1" to limit
STUDIES     ?= $(sort $(wildcard study/*.toml))
STUDY_FLAGS ?= --nice 10
# the porous-region cases of doc/porous.md and their table (about 40 s on one core)
# the same breakwater (regular placement) on a porous and on an impermeable core at the
# same numerics (those the pores need), from the settling to BWC_END: the water level in
# the core, the pressure under the armour, the uplift on the units, side by side
# (doc/porous.md, doc/img/breakwater_core.png)
BWC_END ?= 10.0
breakwater_core: deps build/mbsph
	@mkdir -p OUT/breakwater_core
	@for core in porous impermeable; do \
	  sed -e "s/t_end = 1.0/t_end = $(BWC_END)/" -e "s/dt_out = 0.25/dt_out = 0.1/" \
	    -e "s#out_dir = 'OUT/breakwater_regular_porous'#out_dir = 'OUT/breakwater_core/$$core'#" \
	    -e "s/core = 'porous'/core = '$$core'/" input/breakwater/regular_porous.nml > OUT/breakwater_core/$$core.nml; \
	done
	$(MPIRUN) -np 1 build/mbsph OUT/breakwater_core/porous.nml > OUT/breakwater_core/porous.log & \
	$(MPIRUN) -np 1 build/mbsph OUT/breakwater_core/impermeable.nml > OUT/breakwater_core/impermeable.log; \
	wait
	$(PYTHON) -m post.breakwater_core OUT/breakwater_core/porous OUT/breakwater_core/impermeable --t-start 3.5 \
	  --out doc/img/breakwater_core.png --table OUT/breakwater_core/table.md

# regular waves on a rectangular porous breakwater: reflection and transmission against
# Madsen (1974), and the same flume without it for its own decay (doc/porous.md); the
# two runs side by side, one core each. PW_DP: the particle spacing [m]
PW_DP ?= 0.015
porous_waves: deps build/mbsph
	$(PYTHON) -m post.porous_waves --write OUT/porous_waves.nml --dp $(PW_DP)
	$(PYTHON) -m post.porous_waves --write OUT/porous_waves_empty.nml --dp $(PW_DP) --no-structure
	build/mbsph OUT/porous_waves.nml > /dev/null & pid=$$!; \
	  build/mbsph OUT/porous_waves_empty.nml > /dev/null; st=$$?; wait $$pid && test $$st = 0
	$(PYTHON) -m post.porous_waves OUT/porous_waves --empty OUT/porous_waves_empty

porous: deps build/mbsph
	$(PYTHON) -m post.porous_cases --bin build/mbsph --out OUT/porous

study: deps build/mbsph
	$(PYTHON) -m post.study $(STUDIES) --doc doc/accuracy-cost.md --img doc/img --cost cpu_s $(STUDY_FLAGS)

bench: deps build/mbsph
	$(PYTHON) bench/run_bench.py

# unused effects cost nothing: the benchmark fluid-only, with a body far from the water,
# and with every optional model on (doc/performance.md#effects-that-are-off);
# BENCH_REF=path/to/mbsph also runs the fluid-only case with another build
bench-effects: deps build/mbsph
	$(PYTHON) bench/run_effects.py $(if $(BENCH_REF),--reference $(BENCH_REF))

# strong and weak scaling on 1 and 2 MPI ranks (doc/performance.md#several-ranks)
bench-mpi: deps build/mbsph
	$(PYTHON) bench/run_mpi.py strong
	$(PYTHON) bench/run_mpi.py weak

clean:
	rm -rf build
