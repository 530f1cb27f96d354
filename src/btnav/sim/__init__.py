"""The pymunk world: scene, diff-drive robot, odometry and sensors."""
