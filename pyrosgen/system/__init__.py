"""Systems of nodes (DESIGN.md section 10): the system model
(:mod:`.model`, ROS names :mod:`.names`), the checks across nodes and the
chains (:mod:`.checks`), cached parallel generation (:mod:`.generate`)
and the system's certificate (:mod:`.certificate`)."""
