"""Physics of lcefem: material laws, the spontaneous-strain tensor, heat sources, empirical laws.

Unit system (used everywhere inside lcefem; convert only at the command line and in plots):

    length mm, time s, force N, stress MPa (N/mm^2), energy mJ (N mm), power mW (mJ/s),
    mass tonne (N s^2/mm), temperature degrees C (differences in K).

Derived: density t/mm^3 (1 g/cm^3 = 1e-9 t/mm^3), specific heat mJ/(t K) (1 J/(g K) = 1e9),
conductivity mW/(mm K) (numerically equal to W/(m K)), film coefficient mW/(mm^2 K)
(1 W/(m^2 K) = 1e-3). ``lcefem.models.units`` holds the conversion factors.

No solver loops, file I/O or plotting live here.
"""
