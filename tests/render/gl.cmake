# GL tests: golden images of the particle layers on EGL and OSMesa (skipped cleanly when
# a backend cannot make a context).
grainflow_add_tests(grainflow_tests_gl gl_render_test.cpp LIBS grainflow_render)
