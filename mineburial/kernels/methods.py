"""The step methods of the integration core (:mod:`.core`): their names and codes, in one table.

Every system of the core offers each of them: the multibody systems by name (``numerics.integrator`` of
the restraint, :func:`mineburial.multibody.integrate`), the falling mine after its own composites
(``scenario_fields.INTEGRATOR_NAMES``). A method's code is its index here; a system's own steps (the
mine's ``local_linear``) have codes from :data:`OWN_METHOD` up and are reached through the system's
``own_step`` (:class:`.core.System`). This module imports nothing, so that the scenario tables read it
without numba (as :mod:`.status`).
"""

#: name of each method of the core (code = index): Dormand-Prince 5(4) (adaptive, error-controlled),
#: classical Runge-Kutta at a fixed step, the Rosenbrock-W method ROS34PW2 (adaptive, linearly implicit)
METHOD_NAMES = ("dopri5", "rk4", "ros34pw2")
#: whether the method chooses its steps by its error estimate (else it steps at the fixed numerics.dt)
ADAPTIVE = (True, False, True)

DOPRI5 = METHOD_NAMES.index("dopri5")
RK4 = METHOD_NAMES.index("rk4")
ROS34PW2 = METHOD_NAMES.index("ros34pw2")

#: codes from here up are a system's own fixed steps (the mine's local_linear is OWN_METHOD)
OWN_METHOD = 1000
