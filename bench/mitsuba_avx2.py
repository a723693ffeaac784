"""Run ../shared/peers/mitsuba_render.py (same arguments) with Dr.Jit's LLVM back end held to
AVX2: 8 lanes per instruction and no AVX-512, whatever the CPU has. On a CPU with AVX-512,
Dr.Jit otherwise compiles 16-lane kernels; this row tells how much of the llvm variant's lead
is AVX-512, and matches what it does on AVX2-only hosts, so ratios compare across machines.

Usage: python bench/mitsuba_avx2.py PEERS_SCRIPT [its arguments]
The target is set through Dr.Jit's C++ function `jit_llvm_set_target(cpu, features, width)`
(libdrjit-core, Dr.Jit 1.x), right after the variant is chosen and before any kernel is built.
"""
import ctypes
import glob
import os
import runpy
import sys

# As the peers script does before it imports Dr.Jit (which reads this once): point it at the
# system's libLLVM 17-20 if there is one.
for lib in sorted(glob.glob("/usr/lib/x86_64-linux-gnu/libLLVM*.so*")):
    if any(v in lib for v in ("17", "18", "19", "20")):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", lib)

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

AVX2_FEATURES = "+avx,+avx2,+fma,+f16c,+bmi,+bmi2,+lzcnt,+popcnt,+sse4.2," \
    "-avx512f,-avx512vl,-avx512bw,-avx512dq,-avx512cd,-evex512"


def hold_to_avx2():
    lib = ctypes.CDLL(dr.__path__[0] + "/libdrjit-core.so")
    try:
        set_target = lib._Z19jit_llvm_set_targetPKcS0_j
        width = lib._Z21jit_llvm_vector_widthv
    except AttributeError:
        sys.exit("this Dr.Jit has no jit_llvm_set_target: cannot hold it to AVX2")
    set_target.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32]
    width.restype = ctypes.c_uint32
    set_target(b"haswell", AVX2_FEATURES.encode(), 8)
    if width() != 8:
        sys.exit(f"Dr.Jit kept a vector width of {width()}, not 8")


original_set_variant = mi.set_variant


def set_variant_avx2(*args, **kwargs):
    original_set_variant(*args, **kwargs)
    hold_to_avx2()


mi.set_variant = set_variant_avx2
script = sys.argv[1]
sys.argv = sys.argv[1:]
runpy.run_path(script, run_name="__main__")
