"""Conversion factors into the lcefem unit system (mm, s, N, MPa, mJ, mW, tonne, degrees C).

Multiply a value in the named unit by the factor to get internal units, e.g.
``5.79 * W`` is 5790 mW.
"""

W = 1.0e3  #: watt -> mW
W_PER_M_K = 1.0  #: W/(m K) -> mW/(mm K)
W_PER_M2_K = 1.0e-3  #: W/(m^2 K) -> mW/(mm^2 K)
G_PER_CM3 = 1.0e-9  #: g/cm^3 -> t/mm^3
J_PER_G_K = 1.0e9  #: J/(g K) -> mJ/(t K)
GPA = 1.0e3  #: GPa -> MPa
GRAM = 1.0e-6  #: g -> t
ZERO_CELSIUS_K = 273.15  #: 0 degrees C in kelvin
STEFAN_BOLTZMANN = (
    5.670374419e-11  #: sigma = 5.670374419e-8 W/(m^2 K^4) in mW/(mm^2 K^4) (CODATA 2018)
)
STANDARD_GRAVITY = 9806.65  #: g_n = 9.80665 m/s^2 in mm/s^2
