"""hw's one base exception: every error class of hw (devices, codecs, drivers, emulators, the
simulator) derives from ``HwError``, beside its other base (``ValueError``, ``OSError``, ...)."""

from __future__ import annotations


class HwError(Exception):
    """Base of hw's errors (``DeviceConfigError``, ``KobukiError``, ``ScipError``, ``Unplugged``,
    ``WorldError``, ...)."""
