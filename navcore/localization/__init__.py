"""Localisation: AMCL (particle filter on a map) and EKF odometry/IMU fusion."""

from navcore.localization.amcl import Amcl
from navcore.localization.amcl_params import AMCL_PARAMS
from navcore.localization.ekf import EKF_PARAMS, Ekf

__all__ = ["Amcl", "AMCL_PARAMS", "Ekf", "EKF_PARAMS"]
