"""The command, the library and the Python module refuse the same values with the same message.

Every keyword Fusion() and add_scans() take is tried with values of its type around the
bounds the options check; the command is run with the same value as the option of the same
name. Both must accept it, or both refuse it with the same message. The keywords come from the
module itself (its unknown-setting message lists them), so a setting added later is walked too.
Run with PYTHONPATH at the built module and RANGEFUSE_BIN at the command.
"""
import math
import os
import re
import subprocess

import pytest
import rangefuse

BIN = os.environ.get("RANGEFUSE_BIN", "rangefuse")
FLOATS = [-1.0, 0.0, 0.5, 2.0, 91.0, 181.0, 1001.0, math.inf, math.nan]
INTS = [-1, 0, 1, 2, 65]
TEXTS = ["", "auto", "rgb", "none", "bogus"]
BOOLS = [True, False]


def text_of(value):
    """The value as the command line writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if not isinstance(value, str) else value


def command_refusal(option, value, missing):
    """The command's message about --option VALUE, or None when it is not about the option."""
    result = subprocess.run(
        [BIN, "fuse", "--scans", missing, "--voxel", "0.01", "--out", missing + ".ply",
         "--" + option, text_of(value)],
        capture_output=True, text=True, check=False)
    assert result.returncode != 0, "a scan list that is not there was accepted"
    message = re.sub(r"^rangefuse: error: ", "", result.stderr.strip().splitlines()[-1])
    message = re.sub(r" \(see 'rangefuse fuse --help'\)$", "", message)
    return message if message.startswith("--" + option) else None


def library_refusal(call):
    """Python's message when `call` refuses its value; None when it accepts it; "type" when the
    value is not of the keyword's type."""
    try:
        call()
    except ValueError as e:
        return str(e)
    except (TypeError, RuntimeError):
        return "type"
    return None


def keywords_of(call):
    """The keywords an unknown-setting message of `call` names."""
    with pytest.raises(ValueError) as e:
        call()
    return re.search(r"\(settings: ([^)]*)\)", str(e.value)).group(1).split(", ")


def agree(option, value, library, missing):
    mine = library_refusal(library)
    if mine == "type":
        return 0
    theirs = command_refusal(option, value, missing)
    if theirs and re.search(r"is not (a number|a whole number|true or false)$", theirs):
        return 0  # Python took it as another type (True as 1.0): not a value of this option
    if mine is not None and not mine.startswith("--" + option):
        mine = None  # refused for something else (the missing scans)
    assert mine == theirs, f"--{option} {text_of(value)}: Python {mine!r}, command {theirs!r}"
    return 1


def test_fusion_keywords_agree_with_the_command(tmp_path):
    missing = str(tmp_path / "none.conf")
    keywords = keywords_of(lambda: rangefuse.Fusion(voxel=0.01, no_such_setting=1))
    assert "min_views" in keywords and "envelope" in keywords
    tried = 0
    for keyword in keywords:
        option = keyword.replace("_", "-")
        for value in FLOATS + INTS + TEXTS + BOOLS:
            tried += agree(option, value,
                           lambda: rangefuse.Fusion(voxel=0.01, **{keyword: value}), missing)
    assert tried > 50


def test_scan_reading_keywords_agree_with_the_command(tmp_path):
    missing = str(tmp_path / "none.conf")
    fusion = rangefuse.Fusion(voxel=0.01)
    tried = 0
    for keyword in ["depth_max", "depth_scale", "format", "intrinsics"]:
        option = {"format": "scan-format"}.get(keyword, keyword.replace("_", "-"))
        for value in FLOATS + TEXTS:
            tried += agree(option, value,
                           lambda: fusion.add_scans(missing, **{keyword: value}), missing)
    assert tried > 20


def test_min_views_zero_is_refused_as_the_command_refuses_it():
    with pytest.raises(ValueError, match=r"^--min-views must be at least 1$"):
        rangefuse.Fusion(voxel=0.01, min_views=0)


def test_old_depth_names_still_work_and_warn(tmp_path):
    fusion = rangefuse.Fusion(voxel=0.01)
    with pytest.warns(FutureWarning, match="depth_max"):
        with pytest.raises(ValueError):  # the list is not there: read after the warning
            fusion.add_scans(str(tmp_path / "none.conf"), max_depth=2.0)
