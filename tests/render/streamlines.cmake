# Streamline geometry (render/layers/streamlines.*): analytic flows, seeding, robustness.
grainflow_add_tests(grainflow_tests_streamlines streamlines_test.cpp LIBS grainflow_render)
