file(REMOVE_RECURSE
  "libbullet_bridge.a"
)
