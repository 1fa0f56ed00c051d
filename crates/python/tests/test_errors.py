"""Bad files, bad options and missing GPUs raise strata's exceptions with the
command line's messages: the file, keyword and line or record named."""

import os
import subprocess
import sys

import numpy as np
import pytest

import strata

from conftest import SAMPLE


def test_the_exceptions_form_one_family():
    for e in (strata.FileError, strata.OptionError, strata.GpuError, strata.NoAdapterError):
        assert issubclass(e, strata.StrataError)
    assert issubclass(strata.NoAdapterError, strata.GpuError)


def test_a_missing_file_is_named(tmp_path):
    missing = tmp_path / "nowhere.egrid"
    with pytest.raises(strata.FileError, match="nowhere.egrid"):
        strata.open(missing)


def test_a_bad_number_names_file_line_and_keyword(tmp_path):
    deck = tmp_path / "bad.grdecl"
    deck.write_text("SPECGRID\n 2 2 1 1 F /\nCOORD\n 0 0 0 0 0 1\n x 1 0 /\n")
    with pytest.raises(strata.FileError) as raised:
        strata.open(deck)
    said = str(raised.value)
    assert "bad.grdecl:5" in said and "COORD" in said, said


def test_a_truncated_egrid_names_its_record(tmp_path):
    whole = tmp_path / "whole.egrid"
    strata.synth(nx=4, ny=3, nz=2).save(whole)
    cut = tmp_path / "cut.egrid"
    cut.write_bytes(whole.read_bytes()[: whole.stat().st_size // 2])
    with pytest.raises(strata.FileError) as raised:
        strata.open(cut)
    said = str(raised.value)
    assert "cut.egrid" in said and "record" in said, said


def test_binary_data_is_not_taken_for_a_model(tmp_path):
    junk = tmp_path / "junk.grdecl"
    junk.write_bytes(b"SPECGRID\x00\x01\x02")
    with pytest.raises(strata.FileError, match="junk.grdecl.*binary data"):
        strata.open(junk)


def test_a_bad_property_deck_names_the_deck(tmp_path):
    deck = tmp_path / "poro.grdecl"
    deck.write_text("PORO\n 0.1 0.2 /\n")
    with pytest.raises(strata.FileError, match="poro.grdecl"):
        strata.open(SAMPLE, props=[deck])


@pytest.mark.parametrize(
    "fields, named",
    [
        ({"bogus": 1}, "bogus"),
        ({"wire": {"thickness": "thick"}}, "wire.thickness"),
        ({"wire": {"thickness": -1}}, "thickness"),
        ({"wire": {"technique": "crayon"}}, "wire.technique.*one of"),
        ({"camera": {"azimuth": 10, "zoom": 2}}, "camera.*zoom"),
        ({"size": [0, 10]}, "size"),
        ({"layers": [3, 1]}, "layers"),
    ],
)
def test_a_bad_scene_field_is_named(fields, named):
    with pytest.raises(strata.OptionError, match=named):
        strata.Scene(**fields)


def test_a_scene_asking_what_the_model_lacks_is_refused():
    with pytest.raises(strata.OptionError, match="layer"):
        strata.render(SAMPLE, strata.Scene(layers=[1, 999], size=[64, 48]))


def test_arrays_of_the_wrong_size_are_refused():
    with pytest.raises(strata.OptionError, match="ZCORN"):
        strata._strata._Grid.from_arrays(
            (1, 1, 1), np.zeros(24), np.zeros(7, np.float32), np.ones(1, bool), {}, "bad"
        )


def test_no_adapter_is_its_own_exception():
    # An adapter name no device has: strata finds no adapter.
    code = (
        "import strata\n"
        "try:\n"
        "    strata.render(strata.synth(nx=2, ny=2, nz=1), size=[8, 8])\n"
        "except strata.NoAdapterError as e:\n"
        "    print('raised:', e)\n"
    )
    env = dict(os.environ, WGPU_ADAPTER_NAME="no such adapter anywhere")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert "raised: no GPU adapter found" in out.stdout, out.stdout + out.stderr
