"""Cortex-M cross builds of emitted models and the controller, and their runs under QEMU."""
