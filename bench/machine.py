"""What every benchmark table names: the machine it ran on.

A cloud VM's "model name" can be the same for different processors ("AMD EPYC" was a Zen 3
without AVX-512 on one day and a CPU with AVX-512 on another, and consph's neighbour search takes
a different path on each), so the name comes with the family, model and widest vector extension.
"""
import os
import platform


def _cpuinfo():
    """The first processor's fields from /proc/cpuinfo (Linux), else {}."""
    fields = {}
    try:
        for line in open("/proc/cpuinfo"):
            if not line.strip():
                break
            key, _, value = line.partition(":")
            fields[key.strip()] = value.strip()
    except OSError:
        pass
    return fields


def cpu_model():
    """The CPU model, with family / model and the widest SIMD extension where Linux says them."""
    info = _cpuinfo()
    name = info.get("model name") or platform.processor() or "unknown"
    flags = set(info.get("flags", "").split())
    simd = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else None
    details = []
    if "cpu family" in info and "model" in info:
        details.append("family %s model %s" % (info["cpu family"], info["model"]))
    if simd:
        details.append(simd)
    return "%s (%s)" % (name, ", ".join(details)) if details else name


def machine_line():
    return "%s, %d cores" % (cpu_model(), os.cpu_count())
