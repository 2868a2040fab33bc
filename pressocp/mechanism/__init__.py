"""Mechanisms: what a linkage gives the model builder (`Linkage`, `Mechanism`) and the linkages
(`SliderCrank`).

A linkage states its generalised coordinates, its kinetic and potential energies, the joints where
a clearance may sit and the ram's height, all symbolic; `pressocp.model.build_model` derives the
equations of motion from them, adds the contact and process forces and locks what is ideal. A new
linkage is one module here that implements `Mechanism.linkage`.
"""

from .base import Linkage, Mechanism
from .slider_crank import SLIDER_CRANK, SliderCrank

__all__ = ["Linkage", "Mechanism", "SLIDER_CRANK", "SliderCrank"]
