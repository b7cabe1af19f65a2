"""Build an Arduino sketch of a library layout (arduino/make_library.py) for
the ATmega328P (Arduino Uno) the way the Arduino IDE does, from Debian
packages: gcc-avr, avr-libc and arduino-core-avr (the core and the
"standard" variant).  The library's C and the sketch are compiled with
warnings as errors (the library with the project's C flags, the sketch as
C++ after the IDE's one preprocessing step, #include <Arduino.h>); the core
is third-party code, compiled once per flag set without -Werror."""
from __future__ import annotations

import re
import shutil
from pathlib import Path

from lab.mcu.build_avr import AVR_CFLAGS, AVR_F_CPU, AVR_MCU, avr_section_sizes, avr_symbols
from lab.mcu.toolchain import BUILD_DIR, Image, McuError, cache_key, file_key, run_tool, tool

ARDUINO_AVR = Path("/usr/share/arduino/hardware/arduino/avr")
CORE = ARDUINO_AVR / "cores" / "arduino"
VARIANT = ARDUINO_AVR / "variants" / "standard"
ARDUINO_DEFS = [f"-mmcu={AVR_MCU}", f"-DF_CPU={AVR_F_CPU}L", "-DARDUINO=10807", "-DARDUINO_AVR_UNO",
                "-DARDUINO_ARCH_AVR", "-Os", "-ffunction-sections", "-fdata-sections"]
CXXFLAGS = ["-std=gnu++11", "-fno-exceptions", "-fno-threadsafe-statics", "-Wall", "-Wextra",
            "-Werror"]
UNO_FLASH, UNO_RAM = 32256, 2048     # flash left by the Uno's bootloader; SRAM


def core_archive() -> Path:
    """The Arduino core and the Uno's variant as core.a, cached by content."""
    if not (CORE / "Arduino.h").exists():
        raise McuError(f"{CORE}/Arduino.h missing (Debian package arduino-core-avr)")
    srcs = sorted([*CORE.glob("*.c"), *CORE.glob("*.cpp"), *CORE.glob("*.S")])
    out = BUILD_DIR / "arduino-core" / file_key(srcs)
    lib = out / "core.a"
    if lib.exists():
        return lib
    tmp = out.with_name(out.name + ".tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    inc = [f"-I{CORE}", f"-I{VARIANT}"]
    objs = []
    for s in srcs:
        o = tmp / (s.name + ".o")
        if s.suffix == ".cpp":
            # gcc-avr 5's float.h defines DECIMAL_DIG for C99 only; WString.cpp needs it
            run_tool([tool("avr-g++"), *ARDUINO_DEFS, "-std=gnu++11", "-fno-exceptions",
                      "-fno-threadsafe-statics", "-w", "-DDECIMAL_DIG=__DECIMAL_DIG__", *inc,
                      "-c", s, "-o", o])
        else:
            run_tool([tool("avr-gcc"), *ARDUINO_DEFS, "-std=gnu11", "-w", "-x",
                      "assembler-with-cpp" if s.suffix == ".S" else "c", *inc, "-c", s, "-o", o])
        objs.append(o)
    run_tool([tool("avr-gcc-ar", "avr-ar"), "rcs", tmp / "core.a", *objs])
    shutil.rmtree(out, ignore_errors=True)
    tmp.rename(out)
    return lib


def build_sketch(library: Path, example: str) -> dict:
    """Compile library/examples/<example>/<example>.ino with the library's
    src/ and the core; {"elf", "flash_bytes", "ram_bytes"} (static RAM:
    .data + .bss).  McuError on any warning or error, or if the program
    does not fit the Uno."""
    library = Path(library)
    sketch_dir = library / "examples" / example
    ino = sketch_dir / f"{example}.ino"
    out = BUILD_DIR / "arduino" / f"{example}-{cache_key(library, ino.read_text())}"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    inc = [f"-I{library / 'src'}", f"-I{sketch_dir}", f"-I{CORE}", f"-I{VARIANT}"]
    objs = []
    for c in sorted((library / "src").glob("*.c")):
        o = out / (c.stem + ".o")
        text = run_tool([tool("avr-gcc"), *AVR_CFLAGS, *inc, "-c", c, "-o", o])
        if "warning" in text.lower():
            raise McuError(f"avr-gcc warning in {c.name}:\n{text}")
        objs.append(o)
    cpp = out / f"{example}.ino.cpp"            # the IDE's step: Arduino.h first
    cpp.write_text(f'#include <Arduino.h>\n#line 1 "{ino}"\n' + ino.read_text())
    o = out / f"{example}.ino.o"
    text = run_tool([tool("avr-g++"), *ARDUINO_DEFS, *CXXFLAGS, *inc, "-c", cpp, "-o", o])
    if "warning" in text.lower():
        raise McuError(f"avr-g++ warning in {ino.name}:\n{text}")
    elf = out / f"{example}.elf"
    run_tool([tool("avr-gcc"), f"-mmcu={AVR_MCU}", "-Os", "-Wl,--gc-sections", o, *objs,
              core_archive(), "-lm", "-o", elf])
    img = Image("avr", elf)
    avr_symbols(img)
    sec = avr_section_sizes(img)
    flash, ram = sec["text"] + sec["data"], sec.get("data", 0) + sec.get("bss", 0)
    if flash > UNO_FLASH or ram > UNO_RAM:
        raise McuError(f"{example}: {flash} B flash, {ram} B RAM: does not fit the Uno")
    return {"elf": elf, "flash_bytes": flash, "ram_bytes": ram, "symbols": img.symbols}
