"""A valid case file and small edits of it, shared by the case-file tests."""

BASE = """
title = "test case"
[surface]
model = "self-affine"
h_rms = "44 um"
hurst = 0.8
rolloff_wavevector = "9.1e3 1/m"
cutoff_wavelength = "20 um"
[rubber]
youngs_modulus = "2.3 MPa"
poisson_ratio = 0.5
[seal]
shape = "ring"
inner_diameter = "3 cm"
outer_diameter = "4 cm"
[fluid]
viscosity = "1 mPa*s"
[conditions]
squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]
pressure_difference = "10 kPa"
[theory]
alpha = 0.2
"""


def edit(old, new, text=BASE):
    assert old in text, old
    return text.replace(old, new)
