# Vesuvius — one GNU Makefile. `make help` lists the targets.
#   make            build the library and tools into build/
#   make test       build and run every test (ends with "N passed, N failed")
#   make test SAN=1 the same with AddressSanitizer and UBSan (build-san/)
#   make demo       install what is missing, build, run the main job on samples/
#   make bench      run the benchmarks in bench/ (results: bench/RESULTS.md)
#   make install    PREFIX=/usr/local DESTDIR=
#   make fuzz       build libFuzzer targets with clang (build-fuzz/)
#   V=1 for verbose commands, WERROR=1 (default under CI) for -Werror.

PREFIX ?= /usr/local
DESTDIR ?=
BINDIR = $(PREFIX)/bin
LIBDIR = $(PREFIX)/lib
INCDIR = $(PREFIX)/include/vesuvius
MANDIR = $(PREFIX)/share/man

CC ?= cc
CXX ?= c++
PKG_CONFIG ?= pkg-config
SHARED ?= ../shared

PKGS = libzstd geographiclib netcdf libpng OpenEXR tbb blosc Imath
# OpenVDB (libopenvdb-dev) ships no pkg-config file: its header and -lopenvdb,
# with its own dependencies (tbb, blosc, Imath) through pkg-config above
OPENVDB_LIBS = -lopenvdb
# the desktop viewer (vsv-play) only
VIEWER_PKGS = glfw3 gl freetype2 fontconfig
ifeq ($(SAN),1)
  B = build-san
  SANFLAGS = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
  OPT = -O1 -g
else
  B = build
  SANFLAGS =
  OPT = -O3 -g
endif
WERROR ?= $(if $(CI),1,0)
ifeq ($(WERROR),1)
  WFLAGS_ERR = -Werror
endif

ifneq ($(MAKECMDGOALS),clean)
  MISSING := $(foreach p,$(PKGS) $(VIEWER_PKGS),$(if $(shell $(PKG_CONFIG) --exists $(p) && echo y),,$(p)))
  ifneq ($(strip $(MISSING)),)
    $(error missing libraries (pkg-config): $(MISSING); run: sudo apt-get install -y $(shell sh tools/deps.sh --names))
  endif
endif

PKG_CFLAGS := $(shell $(PKG_CONFIG) --cflags $(PKGS) 2>/dev/null)
PKG_LIBS := $(shell $(PKG_CONFIG) --libs $(PKGS) 2>/dev/null)
VIEWER_CFLAGS := $(shell $(PKG_CONFIG) --cflags $(VIEWER_PKGS) 2>/dev/null)
VIEWER_LIBS := $(shell $(PKG_CONFIG) --libs $(VIEWER_PKGS) 2>/dev/null)

# Truncating text into fixed-size info fields is by design, hence no -Wformat-truncation.
WARN = -Wall -Wextra -Wshadow -Wno-format-truncation $(WFLAGS_ERR)
CFLAGS_ALL = -std=c11 -D_GNU_SOURCE -fPIC $(OPT) $(WARN) -Wstrict-prototypes $(SANFLAGS) -pthread -MMD -MP \
             -Iformat -Iconvert -Irender -Istream -Iviewer -Iinterop $(PKG_CFLAGS) $(CFLAGS)
CXXFLAGS_ALL = -std=c++17 -fPIC $(OPT) $(WARN) $(SANFLAGS) -pthread -MMD -MP -Iformat -Iinterop $(PKG_CFLAGS) $(CXXFLAGS)
LDLIBS_ALL = $(SANFLAGS) -pthread $(OPENVDB_LIBS) $(PKG_LIBS) -lstdc++ -lm $(LDLIBS)

ifeq ($(V),1)
  Q =
else
  Q = @
endif

# program code that is not part of the library: vsv-convert's command line,
# shared with vsv-convert-mpi
CONVERT_CLI = convert/vsv_convert_cli.c
LIB_C = $(filter-out $(CONVERT_CLI),$(wildcard format/vsv_*.c) $(wildcard convert/vsv_*.c)) $(wildcard interop/vsv_*.c) $(wildcard render/vsv_*.c) \
        $(wildcard stream/vsv_*.c) viewer/vsv_player.c viewer/vsv_freevr_conf.c
LIB_CXX = $(wildcard format/vsv_*.cc) $(wildcard interop/vsv_*.cc)
LIB_OBJ = $(patsubst %.c,$(B)/%.o,$(LIB_C)) $(patsubst %.cc,$(B)/%.o,$(LIB_CXX))
LIB = $(B)/libvesuvius.a
VERSION := $(shell sed -n 's/^\#define VSV_VERSION_STRING "\(.*\)"/\1/p' format/vsv_format.h)
SOVERSION = 0
SHLIB = $(B)/libvesuvius.so.$(VERSION)
DATADIR = $(PREFIX)/share

TOOLS = vsv-pack vsv-info vsv-extract vsv-interp vsv-convert vsv-render vsv-play vsv-export vsv-query
TOOL_BIN = $(addprefix $(B)/,$(TOOLS))

TEST_SRC = $(wildcard tests/test_*.c)
TEST_BIN = $(patsubst tests/%.c,$(B)/tests/%,$(TEST_SRC))
TEST_HELPERS = $(B)/tests/vsv_refread.o $(B)/tests/vsv_testlib.o $(B)/tests/vsv_synth.o
FUZZ_BIN = $(B)/tests/test_fuzz $(B)/tests/test_fuzz_mm5 $(B)/tests/test_fuzz_uamiv

# The Python module `vesuvius` (python/): the CPython and NumPy C APIs from
# Debian's python3-dev and python3-numpy, the library linked in statically.
# Skipped, with a note, where they are missing, and under SAN=1 (an ASan
# build cannot be loaded into a python3 that was not started with it).
PYTHON ?= /usr/bin/python3
PY_INC := $(shell $(PYTHON) -c "import sysconfig; print(sysconfig.get_paths()['include'])" 2>/dev/null)
PY_NUMPY_INC := $(shell $(PYTHON) -c "import numpy; print(numpy.get_include())" 2>/dev/null)
PY_EXT := $(shell $(PYTHON) -c "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))" 2>/dev/null)
PY_MISSING := $(if $(wildcard $(PY_INC)/Python.h),,python3-dev )$(if $(PY_NUMPY_INC),,python3-numpy)
PY_MISSING := $(if $(strip $(PY_MISSING)),apt-get install $(PY_MISSING))
PYDIR = $(PREFIX)/lib/python3/dist-packages
ifeq ($(SAN),1)
  PY_MISSING := not under SAN=1
endif
ifeq ($(strip $(PY_MISSING)),)
  PYMOD = $(B)/python/vesuvius/_vesuvius$(PY_EXT) $(B)/python/vesuvius/__init__.py
endif

.PHONY: all test demo bench install uninstall clean fuzz help deps freevr freevr-syntax
.SECONDARY:
all: $(LIB) $(SHLIB) $(TOOL_BIN) $(PYMOD)
ifneq ($(strip $(PY_MISSING)),)
	@echo "note: the Python module is not built: $(PY_MISSING)"
endif

$(B)/python/vsv_python.o: python/vsv_python.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CFLAGS_ALL) -I$(PY_INC) -I$(PY_NUMPY_INC) -c $< -o $@

$(B)/python/vesuvius/_vesuvius$(PY_EXT): $(B)/python/vsv_python.o $(LIB)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -shared -o $@ $< $(LIB) -Wl,--as-needed $(LDLIBS_ALL)

$(B)/python/vesuvius/%.py: python/vesuvius/%.py
	@mkdir -p $(dir $@)
	$(Q)cp $< $@

help:
	@sed -n '2,10p' Makefile | sed 's/^# *//'

$(B)/%.o: %.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CFLAGS_ALL) -c $< -o $@

# the raycaster's sixteen-ray march: AVX2 + FMA code, called only on CPUs that have them
$(B)/render/vsv_raycast_simd.o: CFLAGS_ALL += -mavx2 -mfma
$(B)/render/vsv_raycast_avx512.o: CFLAGS_ALL += -mavx2 -mfma -mavx512f
# the shear-warp's eight-pixel rows, built for any x86-64 (its eight-float
# vectors never cross a call, so -Wpsabi's ABI note is moot) and for AVX2 + FMA
$(B)/render/vsv_sw_row.o: CFLAGS_ALL += -Wno-psabi
$(B)/render/vsv_sw_row_avx2.o: CFLAGS_ALL += -mavx2 -mfma -mf16c -ffp-contract=fast

$(B)/%.o: %.cc
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CXX     $<")
	$(Q)$(CXX) $(CXXFLAGS_ALL) -c $< -o $@

$(LIB): $(LIB_OBJ)
	@$(if $(Q),echo "  AR      $@")
	$(Q)rm -f $@ && ar rcs $@ $^

# the shared library: versioned file, soname libvesuvius.so.$(SOVERSION)
$(SHLIB): $(LIB_OBJ)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -shared -Wl,-soname,libvesuvius.so.$(SOVERSION) -o $@ $^ $(LDLIBS_ALL)

$(B)/vsv-%: $(B)/format/vsv-%.o $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $< $(LIB) $(LDLIBS_ALL)

$(B)/vsv-%: $(B)/convert/vsv-%.o $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $< $(LIB) $(LDLIBS_ALL)

$(B)/vsv-convert: $(B)/convert/vsv-convert.o $(B)/convert/vsv_convert_cli.o $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL)

$(B)/vsv-%: $(B)/interop/vsv-%.o $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $< $(LIB) $(LDLIBS_ALL)

$(B)/vsv-%: $(B)/render/vsv-%.o $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $< $(LIB) $(LDLIBS_ALL)

$(B)/viewer/%.o: viewer/%.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CFLAGS_ALL) $(VIEWER_CFLAGS) -c $< -o $@

$(B)/vsv-play: $(B)/viewer/vsv-play.o $(B)/viewer/vsv_overlay.o $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL) $(VIEWER_LIBS)

# The FreeVR back end: `make FREEVR_DIR=DIR freevr` builds it against a
# FreeVR install (DIR/include/freevr.h, DIR/lib/libfreevr.a; its headers as
# system headers, which -Wstrict-prototypes would reject). `make test` builds
# it against the project's stand-in (tests/freevr-standin/, never installed)
# and checks its syntax against the declarations in viewer/freevr/.
FREEVR_LIBS = -lGL -lX11 -lXi -ldl -lm -lpthread
ifneq ($(FREEVR_DIR),)
TOOLS += vsv-play-freevr
endif
# $(call freevr_link,OUTPUT,FREEVR-DIR)
define freevr_link
	@mkdir -p $(dir $(1))
	@$(if $(Q),echo "  CC/LD   $(1)")
	$(Q)$(CC) $(CFLAGS_ALL) $(VIEWER_CFLAGS) -isystem $(2)/include -o $(1) viewer/vsv-play-freevr.c \
	  $(B)/viewer/vsv_overlay.o $(LIB) $(2)/lib/libfreevr.a $(LDLIBS_ALL) $(VIEWER_LIBS) $(FREEVR_LIBS)
endef
freevr: $(B)/vsv-play-freevr
$(B)/vsv-play-freevr: viewer/vsv-play-freevr.c $(B)/viewer/vsv_overlay.o $(LIB)
	@test -n "$(FREEVR_DIR)" || { echo "vsv-play-freevr needs FreeVR: make FREEVR_DIR=DIR freevr" \
	  "(DIR/include/freevr.h, DIR/lib/libfreevr.a)" >&2; exit 2; }
	@test -f "$(FREEVR_DIR)/include/freevr.h" -a -f "$(FREEVR_DIR)/lib/libfreevr.a" || { echo "FREEVR_DIR=$(FREEVR_DIR):" \
	  "no include/freevr.h or lib/libfreevr.a there" >&2; exit 2; }
	$(call freevr_link,$@,$(FREEVR_DIR))

# the stand-in: FreeVR's calls and conventions (../shared/docs/FREEVR.md)
# written by the project for tests, laid out like an install
STANDIN = $(B)/tests/freevr-standin
$(B)/tests/freevr-standin/freevr.o: CFLAGS_ALL += -isystem viewer/freevr
$(STANDIN)/include/freevr.h: viewer/freevr/freevr.h
	@mkdir -p $(dir $@)
	$(Q)cp $< $@
$(STANDIN)/lib/libfreevr.a: $(B)/tests/freevr-standin/freevr.o
	@mkdir -p $(dir $@)
	$(Q)rm -f $@ && ar rcs $@ $^
$(B)/tests/vsv-play-freevr: viewer/vsv-play-freevr.c $(B)/viewer/vsv_overlay.o $(LIB) $(STANDIN)/include/freevr.h \
                            $(STANDIN)/lib/libfreevr.a
	$(call freevr_link,$@,$(STANDIN))

# syntax only, no dependency file (it would land in the source tree)
freevr-syntax:
	$(Q)$(CC) $(filter-out -MMD -MP,$(CFLAGS_ALL)) $(VIEWER_CFLAGS) -isystem viewer/freevr -fsyntax-only \
	  viewer/vsv-play-freevr.c

$(B)/tests/test_%: $(B)/tests/test_%.o $(TEST_HELPERS) $(LIB)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL)

$(B)/tests/mm5crop: $(B)/tests/mm5_crop.o $(LIB)
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL)

$(B)/tests/test_fuzz: $(B)/tests/fuzz_vsv.o $(B)/tests/fuzz_main.o $(TEST_HELPERS) $(LIB)
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL)

$(B)/tests/test_fuzz_%: $(B)/tests/fuzz_%.o $(B)/tests/fuzz_main.o $(TEST_HELPERS) $(LIB)
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL)

test: all $(TEST_BIN) $(FUZZ_BIN) $(B)/tests/mm5crop $(B)/tests/vsv-play-freevr
	$(Q)B=$(B) SHARED=$(SHARED) SANFLAGS="$(SANFLAGS)" PYTHON=$(PYTHON) PYMOD="$(PYMOD)" PY_MISSING="$(PY_MISSING)" sh tests/run.sh

# The demo: install what is missing (or print the apt-get line), build, then
# run the main job on the bundled sample.
demo:
	$(Q)sh tools/deps.sh --install
	$(Q)$(MAKE) --no-print-directory all $(B)/tests/vsv-play-freevr
	$(Q)B=$(B) sh tools/demo.sh

BENCH_BIN = $(B)/bench/bench_format $(B)/bench/bench_camx $(B)/bench/bench_camx_nc $(B)/bench/bench_render \
            $(B)/bench/bench_play $(B)/bench/bench_advect
$(B)/bench/%: $(B)/bench/%.o $(LIB)
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL)

$(B)/bench/bench_volpack: $(B)/bench/bench_volpack.o $(LIB)
	$(Q)$(CC) -o $@ $^ $(LDLIBS_ALL) -lvolpack

bench: all $(BENCH_BIN)
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_format.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_convert.sh
	$(Q)B=$(B) sh bench/bench_camx.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_advect.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_render.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_play.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_vdb.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_vtk.sh || echo "(VTK comparison skipped)"
	$(Q)if [ -f /usr/include/volpack.h ]; then $(MAKE) --no-print-directory $(B)/bench/bench_volpack && \
	  B=$(B) SHARED=$(SHARED) sh bench/bench_volpack.sh; else echo "(VolPack comparison skipped: apt-get install libvolpack1-dev)"; fi

deps:
	$(Q)sh tools/deps.sh --install

fuzz:
	$(MAKE) B=build-fuzz CC=clang CXX=clang++ SANFLAGS="-fsanitize=fuzzer-no-link,address,undefined" \
	  build-fuzz/libvesuvius.a build-fuzz/tests/fuzz_vsv.o build-fuzz/tests/fuzz_mm5.o build-fuzz/tests/fuzz_uamiv.o
	for t in vsv mm5 uamiv; do clang -fsanitize=fuzzer,address,undefined -o build-fuzz/fuzz_$$t build-fuzz/tests/fuzz_$$t.o \
	  build-fuzz/libvesuvius.a $(PKG_LIBS) -lstdc++ -lm -pthread || exit 1; done
	@echo "run: build-fuzz/fuzz_vsv tests/golden, build-fuzz/fuzz_mm5 tests/corpus/mm5, build-fuzz/fuzz_uamiv tests/corpus/uamiv"

install: all
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCDIR) $(DESTDIR)$(MANDIR)/man1 \
	  $(DESTDIR)$(MANDIR)/man5 $(DESTDIR)$(DATADIR)/vesuvius $(DESTDIR)$(DATADIR)/bash-completion/completions
	install -m 755 $(TOOL_BIN) $(DESTDIR)$(BINDIR)/
	install -m 644 $(LIB) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(SHLIB) $(DESTDIR)$(LIBDIR)/
	ln -sf libvesuvius.so.$(VERSION) $(DESTDIR)$(LIBDIR)/libvesuvius.so.$(SOVERSION)
	ln -sf libvesuvius.so.$(SOVERSION) $(DESTDIR)$(LIBDIR)/libvesuvius.so
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(VERSION)|' tools/vesuvius.pc.in > $(DESTDIR)$(LIBDIR)/pkgconfig/vesuvius.pc
	install -m 644 format/vsv_format.h render/vsv_render.h stream/vsv_pager.h stream/vsv_clock.h viewer/vsv_player.h \
	  $(DESTDIR)$(INCDIR)/
	install -m 644 $(filter-out $(if $(FREEVR_DIR),,man/vsv-play-freevr.1),$(wildcard man/*.1)) $(DESTDIR)$(MANDIR)/man1/
	install -m 644 man/*.5 $(DESTDIR)$(MANDIR)/man5/
	install -m 644 share/transfer-functions.tf $(DESTDIR)$(DATADIR)/vesuvius/
	if [ -n "$(PYMOD)" ]; then install -d $(DESTDIR)$(PYDIR)/vesuvius && install -m 644 $(PYMOD) $(DESTDIR)$(PYDIR)/vesuvius/; fi
	for t in $(TOOLS); do install -m 644 tools/completion/vesuvius.bash $(DESTDIR)$(DATADIR)/bash-completion/completions/$$t; done

uninstall:
	rm -f $(addprefix $(DESTDIR)$(BINDIR)/,$(TOOLS)) $(DESTDIR)$(LIBDIR)/libvesuvius.a $(DESTDIR)$(LIBDIR)/libvesuvius.so*
	rm -f $(DESTDIR)$(LIBDIR)/pkgconfig/vesuvius.pc $(addprefix $(DESTDIR)$(DATADIR)/bash-completion/completions/,$(TOOLS))
	rm -f $(addprefix $(DESTDIR)$(MANDIR)/man1/,$(addsuffix .1,$(TOOLS))) $(DESTDIR)$(MANDIR)/man5/vsv.5
	rm -rf $(DESTDIR)$(INCDIR) $(DESTDIR)$(DATADIR)/vesuvius $(DESTDIR)$(PYDIR)/vesuvius

clean:
	rm -rf build build-san build-fuzz

-include $(shell find $(B) -name '*.d' 2>/dev/null)
