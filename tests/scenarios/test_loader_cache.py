"""Parsed files are cached for speed, but an edited file (or an edited base of a vehicle) is re-read."""
import os
from pathlib import Path

from vehicle_assist.scenarios.loader import load_vehicle, shipped


def test_edited_base_vehicle_is_reread(tmp_path: Path) -> None:
    """A vehicle whose base file changes within one process sees the new base value (cache keyed on the chain)."""
    text = shipped("vehicles")["heavy_amt_truck_empty"].read_text(encoding="utf-8")
    base = tmp_path / "base.toml"
    top = tmp_path / "top.toml"
    base.write_text(text, encoding="utf-8")
    top.write_text(f'name = "t"\nbase = "{base}"\ndescription = "x"\nsource = "x"\n', encoding="utf-8")
    assert load_vehicle(top).model.body.mass_kg == 13000
    base.write_text(text.replace("mass_kg = 13000", "mass_kg = 14000", 1), encoding="utf-8")
    st = base.stat()
    os.utime(base, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))  # a distinct mtime even on coarse clocks
    assert load_vehicle(top).model.body.mass_kg == 14000
