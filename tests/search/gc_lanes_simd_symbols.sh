#!/bin/bash
# The GC rollouts compiled for AVX2 and AVX-512 (search/gc_lanes_simd.hpp) in a build for any
# x86-64. In each object, the code that rolls its own lane type (Lanes<4, kAvx2Isa> or
# Lanes<4, kAvx512Isa>) must use AVX (else the dispatch buys nothing), and every other function the
# object defines for the linker (one another object may define too: a destructor, an inline helper)
# must be free of AVX instructions, or the linker could pick that copy for the whole program and run
# AVX on a CPU without it. Exit 77 (skipped) where the build has no such rollouts.
# Given the core library too, the same for core/sin_cos.cpp (CRBA's sines and cosines): its AVX2
# and AVX-512 functions, local to it, use AVX, and nothing it defines for the linker does.
# Usage: gc_lanes_simd_symbols.sh LIBDYNID_SEARCH.a [LIBDYNID_CORE.a]
set -euo pipefail
archive=$(realpath "$1")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
(cd "$dir" && ar x "$archive" gc_lanes_avx2.cpp.o gc_lanes_avx512.cpp.o)
if (($# > 1)); then
  core=$(realpath "$2")
  (cd "$dir" && ar x "$core" sin_cos.cpp.o)
fi

# Instructions with a VEX or EVEX encoding: their mnemonics start with v (vmovupd, vaddpd, ...).
# (Counted, not grep -q: an early exit would fail objdump's pipe under pipefail.)
uses_avx() {
  local count
  count=$(objdump -d --no-show-raw-insn --disassemble="$2" "$1" |
    grep -cE '^\s+[0-9a-f]+:\s+v[a-z0-9]+\s' || true)
  ((count > 0))
}

check() {
  local object=$1 lanes=$2 name=$3 own=0 shared=0
  if [[ -z $(nm --defined-only "$object" | awk '$2 == "T"') ]]; then
    return 1
  fi
  while read -r _ _ symbol; do
    if [[ $(c++filt "$symbol") == *"$lanes"* ]]; then
      if uses_avx "$object" "$symbol"; then own=$((own + 1)); fi
    else
      shared=$((shared + 1))
      if uses_avx "$object" "$symbol"; then
        echo "FAIL ($name): $(c++filt "$symbol") is compiled with AVX and may replace the" \
          "build's copy" >&2
        exit 1
      fi
    fi
  done < <(nm --defined-only "$object" | awk '$2 ~ /^[TWi]$/')
  local entry
  entry=$(nm --defined-only "$object" | awk '$2 == "T" && /rollOutSegmentsSimd/ {print $3}')
  if [[ -z $entry ]] || ! uses_avx "$object" "$entry"; then
    echo "FAIL ($name): its rollOutSegmentsSimd is missing or has no AVX instructions" >&2
    exit 1
  fi
  echo "ok ($name): $own functions on its lane type use AVX; $shared other functions defined" \
    "for the linker use none"
}

check_sin_cos() {
  local object=$1 symbol own=0
  while read -r _ _ symbol; do
    if uses_avx "$object" "$symbol"; then
      echo "FAIL (sin_cos): $(c++filt "$symbol") is compiled with AVX and may replace the" \
        "build's copy" >&2
      exit 1
    fi
  done < <(nm --defined-only "$object" | awk '$2 ~ /^[TWi]$/')
  while read -r _ _ symbol; do
    if ! uses_avx "$object" "$symbol"; then
      echo "FAIL (sin_cos): $(c++filt "$symbol") has no AVX instructions" >&2
      exit 1
    fi
    own=$((own + 1))
  done < <(nm --defined-only "$object" | awk '$2 == "t" && /sinCosAvx(2|512)/')
  if ((own != 2)); then
    echo "FAIL (sin_cos): $own of its two AVX functions found" >&2
    exit 1
  fi
  echo "ok (sin_cos): its AVX2 and AVX-512 functions use AVX; what it defines for the linker, none"
}

found=0
if [[ -f $dir/sin_cos.cpp.o && $(nm "$dir/sin_cos.cpp.o" | grep -c sinCosAvx || true) -gt 0 ]]; then
  check_sin_cos "$dir/sin_cos.cpp.o"
fi
check "$dir/gc_lanes_avx2.cpp.o" 'Lanes<4, 1>' AVX2 && found=$((found + 1))
check "$dir/gc_lanes_avx512.cpp.o" 'Lanes<4, 2>' AVX-512 && found=$((found + 1))
if ((found == 0)); then
  echo "skipped: this build has no such rollouts (it targets AVX itself, or is not GCC on x86-64)"
  exit 77
fi
if ((found != 2)); then
  echo "FAIL: one of the two rollouts is missing" >&2
  exit 1
fi
