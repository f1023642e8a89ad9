"""World plug-ins that ship with skillwright (see :mod:`skillwright.runtime` for the API)."""
