"""Contact laws by name (`CONTACT_LAWS`): a new law is a module here with a `ContactLaw` subclass and
one line below."""

from .base import ContactLaw, softplus
from .hunt_crossley import HuntCrossley
from .kelvin_voigt import KelvinVoigt

#: The laws by `pressocp.params.Bearing.law`.
CONTACT_LAWS: dict[str, ContactLaw] = {law.name: law for law in (HuntCrossley(), KelvinVoigt())}

__all__ = ["CONTACT_LAWS", "ContactLaw", "HuntCrossley", "KelvinVoigt", "softplus"]
