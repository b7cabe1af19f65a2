"""The device-id section of the coefficient image (format: csrc/include/
sig_device_id.h): which unit an image was made for, so the firmware can
refuse another unit's calibration.

    from ._device import device_section, image_device_status
    image = model_image(model, extra_sections=[device_section("SN-000123")])
    image_device_status(image, "SN-000124")   # -> SIG_ERR_DEVICE (-6)

Serials are text (UTF-8) or bytes; a serial of at most 16 bytes is stored as
it is, a longer one as a 32-bit hash plus its last 12 bytes."""
from ..errors import ModelFileError
from ..status import Status
from ._device_id import check_image, device_id
from ._image import SECTION_DEVICE_ID

SIG_ERR_DEVICE = int(Status.ERR_DEVICE)
MAX_LEN = 16


def serial_bytes(serial):
    """A serial as bytes (text is UTF-8); ValueError when empty."""
    b = serial if isinstance(serial, (bytes, bytearray)) else str(serial).encode("utf-8")
    if not b:
        raise ValueError("a device serial cannot be empty")
    return bytes(b)


def device_section(serial):
    """(SECTION_DEVICE_ID, payload) for build_image / model_image's extra sections."""
    st, (kind, ident) = device_id(serial_bytes(serial))
    if st != 0:
        raise ValueError(f"serial {serial!r}: no device id (status {st})")
    return SECTION_DEVICE_ID, bytes([kind, len(ident)]) + ident


def image_device_status(image, serial):
    """The firmware's answer (sig_device_id_check_image, the C code) for
    `image` on the device whose serial is `serial`: 0 when the image was made
    for it, SIG_ERR_DEVICE (-6) for another device's image or one with no id."""
    return check_image(bytes(image), serial_bytes(serial))


def require_device(image, serial, where="image"):
    """ModelFileError unless `image` was made for the device `serial`."""
    st = image_device_status(image, serial)
    if st == SIG_ERR_DEVICE:
        raise ModelFileError(f"{where}: made for another device, not {serial!r} "
                             f"(the firmware refuses it with SIG_ERR_DEVICE)")
    if st != 0:
        raise ModelFileError(f"{where}: not a valid image for device {serial!r} (status {st})")
