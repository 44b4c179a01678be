"""drape: mass-spring cloth simulation, the Python face of the C++ library.

The classes and functions are the C++ library's, bound with nanobind (module ``drape._drape``);
docs/python.md describes them, and every one has a docstring.

    import drape
    cloth = drape.Cloth(drape.ClothSpec(boundary="one-corner"))
    rk2 = drape.Rk2(cloth, dt=5e-4)
    state = cloth.initial_state()
    rk2.run(state, 1.0)                  # one simulated second, GIL released
    print(state.positions[0])            # numpy view of the C++ state
"""

from ._drape import (
    AerodynamicSettings,
    AirSettings,
    Cloth,
    ClothScene,
    ClothSpec,
    Collider,
    ContactReport,
    FileWriteError,
    GustSettings,
    ImplicitEuler,
    ImplicitOptions,
    Integrator,
    IntegratorOptions,
    InvalidParameter,
    PinPath,
    PinSet,
    Placement,
    Renderer,
    Rk2,
    SceneFile,
    SceneFileError,
    SelfCollisionReport,
    SelfCollisionSettings,
    SimulationError,
    SpringCoefficients,
    SpringParams,
    State,
    StateFormatError,
    StepStatus,
    SymplecticEuler,
    __version__,
    load_scene,
    load_state,
    make_integrator,
    option_names,
    save_state,
    write_obj,
)

__all__ = [
    "AerodynamicSettings",
    "AirSettings",
    "Cloth",
    "ClothScene",
    "ClothSpec",
    "Collider",
    "ContactReport",
    "FileWriteError",
    "GustSettings",
    "ImplicitEuler",
    "ImplicitOptions",
    "Integrator",
    "IntegratorOptions",
    "InvalidParameter",
    "PinPath",
    "PinSet",
    "Placement",
    "Renderer",
    "Rk2",
    "SceneFile",
    "SceneFileError",
    "SelfCollisionReport",
    "SelfCollisionSettings",
    "SimulationError",
    "SpringCoefficients",
    "SpringParams",
    "State",
    "StateFormatError",
    "StepStatus",
    "SymplecticEuler",
    "__version__",
    "load_scene",
    "load_state",
    "make_integrator",
    "option_names",
    "save_state",
    "write_obj",
]
