# Empty dependencies file for bullet_bridge.
# This may be replaced when dependencies are built.
