# Empty dependencies file for xpbd-demo.
# This may be replaced when dependencies are built.
