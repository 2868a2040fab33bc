"""Mechanisms: what a linkage gives the model builder (`Linkage`, `Mechanism`) and the linkages
(`SliderCrank`, `SixBar`, `KnuckleJoint`).

A linkage states its generalised coordinates, its kinetic and potential energies, the joints where
a clearance may sit and the ram's height, all symbolic; `pressocp.model.build_model` derives the
equations of motion from them, adds the contact and process forces and locks what is ideal. A new
linkage is one module here that implements `Mechanism.linkage`.
"""

from .base import Linkage, Mechanism
from .ideal import WorkingZone, constant_speed_zone
from .knuckle import KnuckleJoint, KnucklePress
from .six_bar import SixBar, SixBarPress
from .slider_crank import SLIDER_CRANK, SliderCrank

#: The linkages by name (`Mechanism.name`), for reading a model level back from plain data.
MECHANISMS = {"slider_crank": SliderCrank, "six_bar": SixBar, "knuckle_joint": KnuckleJoint}


def mechanism_to_dict(mechanism: Mechanism) -> dict:
    """Plain data of a mechanism: its name and its fields (`mechanism_from_dict` reads it back)."""
    return {"name": mechanism.name, **mechanism.to_dict()}


def mechanism_from_dict(data: dict) -> Mechanism:
    """The mechanism of `mechanism_to_dict`'s data."""
    name = data.get("name")
    if name not in MECHANISMS:
        raise ValueError(f"mechanism name must be one of {', '.join(MECHANISMS)}; got {name!r}")
    return MECHANISMS[name].from_dict({k: v for k, v in data.items() if k != "name"})


__all__ = ["KnuckleJoint", "KnucklePress", "Linkage", "MECHANISMS", "Mechanism", "SLIDER_CRANK", "SixBar", "SixBarPress", "SliderCrank", "WorkingZone",
           "constant_speed_zone", "mechanism_from_dict", "mechanism_to_dict"]
