"""CiA 301 emergency error codes: their names and classes (:func:`describe_code`), the error register
(0x1001) a code sets (:func:`error_register_for`) and the code a simulated drive's fault raises unless
told otherwise (:data:`DEFAULT_FAULT_CODE`). Numbers and names only: the command line offers the
default without loading a drive."""

from __future__ import annotations

DEFAULT_FAULT_CODE = 0x2310
"""continuous over-current: what a simulated drive's ``--fault-at S`` raises without a code"""

_KNOWN_CODES: dict[int, str] = {
    0x1000: "generic error",
    0x2310: "continuous over-current",
    0x2320: "short circuit at the outputs",
    0x3210: "DC link over-voltage",
    0x3220: "DC link under-voltage",
    0x4210: "device temperature too high",
    0x4310: "drive temperature too high",
    0x5441: "enable input (STO) off",
    0x7305: "incremental sensor 1 fault",
    0x8110: "CAN overrun",
    0x8120: "CAN in error passive mode",
    0x8130: "life guard or heartbeat error",
    0x8140: "recovered from bus off",
    0x8611: "following error",
    0x8612: "reference limit",
    0xFF00: "device specific",
}
_CLASSES: tuple[tuple[int, int, str], ...] = (
    (0xF000, 0x2000, "current"),
    (0xF000, 0x3000, "voltage"),
    (0xF000, 0x4000, "temperature"),
    (0xFF00, 0x5000, "device hardware"),
    (0xF000, 0x6000, "device software"),
    (0xFF00, 0x7000, "additional modules"),
    (0xFF00, 0x8100, "communication"),
    (0xFF00, 0x8600, "positioning controller"),
    (0xF000, 0x8000, "monitoring"),
    (0xFF00, 0x9000, "external error"),
    (0xFF00, 0xFF00, "device specific"),
)


def describe_code(code: int) -> str:
    """``0x2310 continuous over-current`` (a known CiA 301/402 code) or its class (``0x2399 current``)."""
    text = _KNOWN_CODES.get(code)
    if text is None:
        text = next((name for mask, value, name in _CLASSES if code & mask == value), "unknown error class")
    return f"0x{code:04X} {text}"


def error_register_for(code: int) -> int:
    """The CiA 301 error register (0x1001) bits a drive sets with ``code``: bit 0 generic always, then
    1 current, 2 voltage, 3 temperature, 4 communication, 5 device profile (positioning)."""
    register = 0x01
    for mask, value, bit in ((0xF000, 0x2000, 1), (0xF000, 0x3000, 2), (0xF000, 0x4000, 3),
                             (0xFF00, 0x8100, 4), (0xFF00, 0x8600, 5)):  # fmt: skip
        if code & mask == value:
            register |= 1 << bit
    return register
