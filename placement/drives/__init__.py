"""Drives: transmissions and motor models (plug-in families), and the motor trace of a motion."""
