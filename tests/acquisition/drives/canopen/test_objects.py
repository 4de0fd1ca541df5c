"""The objects and the PDO layout: mapping values, frame lengths on the wire, and an EDS file that
lacks an object axisflow needs is refused naming it (canopen's own EDS writer and reader)."""

import canopen
import pytest
from axisflow.acquisition.drives.canopen.config import config_from_mapping
from axisflow.acquisition.drives.canopen.objects import (
    MANDATORY,
    OPTIONAL,
    RPDOS,
    TORQUE_OFFSET,
    TPDOS,
    bits_per_cycle,
    drive_dictionary,
    frame_bits,
    missing_objects,
)
from axisflow.acquisition.drives.canopen.startup import object_dictionary
from axisflow.acquisition.errors import DriveConfigError


def test_the_pdos_fit_classic_can_frames_and_map_what_the_issue_names():
    for layout in (*RPDOS, *TPDOS):
        assert layout.size <= 8
    mapped = {e.index for layout in (*RPDOS, *TPDOS) for e in layout.entries}
    assert mapped == {0x6040, 0x607A, 0x60B1, 0x60B2, 0x6041, 0x6064, 0x606C, 0x6077}
    assert RPDOS[0].mapping_values() == [0x60400010, 0x607A0020, 0x60B20010]
    assert [layout.cob_id(5) for layout in (*RPDOS, *TPDOS)] == [0x205, 0x305, 0x185, 0x285]


def test_frame_lengths_are_the_can_2_0a_arithmetic():
    assert frame_bits(8) == 111 and frame_bits(8, worst_case=True) == 135
    assert frame_bits(4) == 79 and frame_bits(4, worst_case=True) == 95
    assert frame_bits(0) == 47 and frame_bits(0, worst_case=True) == 55
    # one axis at 1 kHz: SYNC + two 8-byte and two 4-byte frames
    assert bits_per_cycle(1) == 47 + 2 * 111 + 2 * 79
    assert bits_per_cycle(1, worst_case=True) == 55 + 2 * 135 + 2 * 95
    with pytest.raises(ValueError, match="0…8 data bytes, not 9"):
        frame_bits(9)


def test_every_object_has_a_reason_and_a_unit_where_it_has_one():
    for entry in (*MANDATORY, *OPTIONAL):
        assert entry.why and entry.name
    assert TORQUE_OFFSET.unit == "per mille of rated torque"


def _eds(tmp_path, leave_out=()):
    path = tmp_path / "drive.eds"
    canopen.export_od(drive_dictionary(5, {}, leave_out), str(path))
    return path


def test_the_drives_own_dictionary_exported_as_eds_has_everything(tmp_path):
    assert missing_objects(canopen.import_od(str(_eds(tmp_path)), 5)) == []


def test_an_eds_lacking_an_object_is_refused_naming_it(tmp_path):
    path = _eds(tmp_path, leave_out=(TORQUE_OFFSET,))
    config = config_from_mapping(
        {
            "can": {"interface": "virtual", "channel": "x"},
            "drive": {"node_id": 5, "encoder_counts_per_rev": 4096, "eds": str(path)},
        }
    )
    with pytest.raises(
        DriveConfigError, match=r"lacks what axisflow needs: 0x60B2 torque offset \(INTEGER16"
    ):
        object_dictionary(config.drives[0])


def test_an_eds_that_is_not_one_is_refused_naming_the_file(tmp_path):
    path = tmp_path / "broken.eds"
    path.write_text("[1000]\nParameterName=device type\nDataType=0x0007\nAccessType=ro\nObjectType=banana\n")
    config = config_from_mapping(
        {
            "can": {"interface": "virtual", "channel": "x"},
            "drive": {"node_id": 5, "encoder_counts_per_rev": 4096, "eds": str(path)},
        }
    )
    with pytest.raises(DriveConfigError, match=r"broken\.eds"):
        object_dictionary(config.drives[0])
