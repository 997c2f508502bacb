// Stub (navlab benchmarks/smac): shadows the checkout's header (tf2, rclcpp); the collision
// checker includes it but uses nothing from it.
