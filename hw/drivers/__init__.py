"""pyserial drivers: one module per device, each a pure codec (``*_codec`` or ``scip``) plus a
driver class that implements the ``hw.interfaces`` protocols."""
