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


#: An O-ring case (the `o-ring` example's seal and surface, water, three compressions).
ORING = """
title = "O-ring test"
[surface]
model = "self-affine"
h_rms = "1.5 um"
hurst = 0.8
rolloff_wavelength = "100 um"
cutoff_wavelength = "10 nm"
[rubber]
youngs_modulus = "5.5 MPa"
poisson_ratio = 0.5
[seal]
shape = "o-ring"
cross_section_diameter = "2.62 mm"
inner_diameter = "20 mm"
[fluid]
name = "water"
viscosity = "1 mPa*s"
[conditions]
compression = ["10 %", "15 %", "30 %"]
pressure_difference = "1 bar"
"""


#: A fine self-affine surface (h_rms 0.3 µm down to 5 nm) on a rubber of 8 MPa: the band, rig and simulation tests'
#: seal, small enough that its contact is light at 0.1-0.6 MPa.
FINE_SURFACE = """
[surface]
model = "self-affine"
h_rms = "0.3 um"
hurst = 0.8
rolloff_wavelength = "50 um"
cutoff_wavelength = "5 nm"
[rubber]
youngs_modulus = "8 MPa"
poisson_ratio = 0.5
"""


def edit(old, new, text=BASE):
    assert old in text, old
    return text.replace(old, new)
