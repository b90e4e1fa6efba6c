#!/usr/bin/env python3
"""Writes cie1931.rs: the CIE 1931 2° standard observer's colour matching
functions x̄, ȳ, z̄ at 1 nm from 360 to 830 nm, as the CIE tabulates them
(CIE 015:2004 "Colorimetry", 3rd ed., table T.4; the CIE's dataset
"CIE 1931 colour-matching functions, 2 degree observer",
doi:10.25039/CIE.DS.xvudnb9b), taken from the copy that colour-science
ships (its MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], from CVRL's
"Older CIE Standards", http://cvrl.ioo.ucl.ac.uk/cie.htm):

    pip install colour-science
    python3 crates/tyndall/src/color/make_cie1931.py > crates/tyndall/src/color/cie1931.rs
"""
import colour

cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
assert (cmfs.wavelengths[0], cmfs.wavelengths[-1], len(cmfs.wavelengths)) == (360, 830, 471)
print("//! The CIE 1931 2° standard observer: x̄, ȳ, z̄ at 1 nm from 360 to")
print("//! 830 nm (CIE 015:2004, table T.4; doi:10.25039/CIE.DS.xvudnb9b).")
print("//! Written by make_cie1931.py; do not edit.")
print()
print("/// Wavelength of the first row, nm; rows are 1 nm apart.")
print("pub const FIRST_NM: u32 = 360;")
print()
print("/// x̄, ȳ, z̄ at `FIRST_NM + row` nm.")
print("#[rustfmt::skip]")
print("pub const CMF: [[f64; 3]; 471] = [")
for w, (x, y, z) in zip(cmfs.wavelengths, cmfs.values):
    print(f"    [{float(x)!r}, {float(y)!r}, {float(z)!r}], // {int(w)}")
print("];")
