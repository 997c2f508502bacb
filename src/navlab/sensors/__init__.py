"""Sensors: a 2D LiDAR with exact ray casting and noise models."""

from .lidar import NOISE_MODELS, GaussianNoise, Lidar, NoiseModel, RPLidarA1Noise

__all__ = ["GaussianNoise", "Lidar", "NOISE_MODELS", "NoiseModel", "RPLidarA1Noise"]
