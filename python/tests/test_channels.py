"""Channels of a multi-channel instrument file (issue #38): `load(channel=)`
as the CLI's `--channel`, against the file's own listing. The file is a
Bruker Nanoscope scan from SurfaceTopography's examples (two height images,
phase, amplitude error); check_instruments.py compares its channels with
SurfaceTopography's."""
from pathlib import Path

import numpy as np
import pytest

import asperity

DI = Path(__file__).resolve().parents[2] / "tests/data/surfacetopography/di-1.di"


def test_the_default_is_the_first_height_channel_and_others_are_picked_by_number_or_name():
    first = asperity.load(DI)
    assert first.heights.shape == (512, 512)
    assert np.array_equal(asperity.load(DI, channel=0).heights, first.heights)
    second = asperity.load(DI, channel=1)
    assert not np.array_equal(second.heights, first.heights)
    phase = asperity.load(DI, channel="phase")
    assert phase.units == ("nm", "none")  # (xy, z): the phase is no length
    assert np.array_equal(asperity.load(DI, channel=2).heights, phase.heights)


def test_a_channel_the_file_lacks_is_refused_with_its_channels():
    with pytest.raises(ValueError, match='no channel "Current".*3 "AmplitudeError"'):
        asperity.load(DI, channel="Current")
    sur = DI.parent / "sur-2.sur"
    with pytest.raises(ValueError, match="holds one channel"):
        asperity.load(sur, channel=1)


def test_a_loaded_field_lists_the_channels_and_keeps_the_instrument_header():
    h = asperity.load(DI)
    assert [c["name"] for c in h.channels] == ["Height", "Height", "Phase", "AmplitudeError"]
    assert [c["height"] for c in h.channels] == [True, True, False, False]
    assert h.instrument["file list\\version"] == "0x07200000"
    plain = asperity.HeightField(np.zeros((2, 2)))
    assert plain.channels is None and plain.instrument is None
