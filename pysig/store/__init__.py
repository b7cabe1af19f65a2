"""The coefficient image: what a device keeps in non-volatile memory.  One
format (``docs/image-format.md``), one reader on the device (``csrc/store``),
CRC-16/CCITT over the whole image, a sequence number for A/B slots, typed
sections (a model's family, the temperature code, the device id).  The store
owns the container; each section's payload belongs to the area whose model
it holds (the temperature models' to ``pysig.tcomp``).

==================  ======================================================
build_image         sections + sequence number -> image bytes (with CRC)
read_image          the checked header and sections of an image
find_section        one section's payload (ModelFileError if absent)
crc16_ccitt         the image's CRC (CRC-16/CCITT-FALSE)
device_section      the section that binds an image to one device's serial
require_device      refuse an image made for another device
SECTION_*           the section types (the same numbers as sig_image.h)
==================  ======================================================
"""
from ._device import device_section, require_device
from ._image import (SECTION_COMPACT_POLY, SECTION_CREEP, SECTION_DEVICE_ID, SECTION_EXPERIMENTAL,
                     SECTION_GAIN_POLY, SECTION_HYSTERESIS, SECTION_LINEAR_SCALE, SECTION_OFFSET_POLY,
                     SECTION_PWL_TABLE, SECTION_TEMP_CODE, SECTION_THERMAL_LAG, SECTION_UNITS, build_image,
                     crc16_ccitt, find_section, read_image)

__all__ = ["build_image", "read_image", "find_section", "crc16_ccitt", "device_section", "require_device",
           "SECTION_OFFSET_POLY", "SECTION_GAIN_POLY", "SECTION_THERMAL_LAG", "SECTION_HYSTERESIS",
           "SECTION_CREEP", "SECTION_PWL_TABLE", "SECTION_LINEAR_SCALE", "SECTION_COMPACT_POLY",
           "SECTION_DEVICE_ID", "SECTION_TEMP_CODE", "SECTION_UNITS", "SECTION_EXPERIMENTAL"]
