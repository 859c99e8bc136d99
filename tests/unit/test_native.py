"""The compiled core's loader and what it says about its build."""

from __future__ import annotations

from bemcontact._native import build_info, core


def test_build_info_says_how_the_core_was_compiled():
    info = build_info()
    assert set(info) == {"native", "compiler", "flags", "build_type", "processor", "openmp"}
    flags = info["flags"].split()
    # the tuning flag and the native switch agree (CMakeLists.txt: BEMCONTACT_NATIVE)
    assert info["native"] is ("-march=native" in flags)
    assert "-O3" in flags and "-fno-math-errno" in flags
    assert info["build_type"] == "Release"
    assert isinstance(info["openmp"], int) and info["openmp"] >= 200805  # OpenMP >= 3.0
    assert info == core().build_info()  # a fresh dict each time, same content
    assert build_info() is not build_info()
