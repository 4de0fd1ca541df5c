"""CiA 301 emergency codes: named (or by class) and the error register bits each sets."""

from axisflow.acquisition.drives.canopen.emergency import (
    DEFAULT_FAULT_CODE,
    describe_code,
    error_register_for,
)


def test_codes_are_described_and_their_register_bits_set():
    assert describe_code(0x8611) == "0x8611 following error"
    assert describe_code(0x2399) == "0x2399 current"
    assert describe_code(0x8199) == "0x8199 communication"
    assert error_register_for(0x2310) == 0x03 and error_register_for(0x8611) == 0x21


def test_the_default_fault_is_a_known_current_fault():
    assert describe_code(DEFAULT_FAULT_CODE) == "0x2310 continuous over-current"
    assert error_register_for(DEFAULT_FAULT_CODE) == 0x03
