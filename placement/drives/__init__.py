"""Drives as data: transmissions and motor models (plug-in families), with their parameters and equations.

The motor trace of a motion and its energy are :mod:`placement.energy`.
"""
