"""What every benchmark table names: the machine it ran on."""
import os
import platform


def cpu_model():
    """The CPU model from /proc/cpuinfo (Linux), else what platform knows."""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def machine_line():
    return "%s, %d cores" % (cpu_model(), os.cpu_count())
