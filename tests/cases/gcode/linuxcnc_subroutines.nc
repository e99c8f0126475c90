G90 G17
N1 (LinuxCNC subroutines as the evaluator runs them: numbered and named,)
N2 (arguments, a return with a value, an endsub with one, repeat counts)
N3 F300.
N3 G21
N13 (DEBUG, small: #<_value> returned #<_value_returned>)
N15 (DEBUG, large: #<_value> returned #<_value_returned>)
N10 G1 X40. Y1.
N10 G1 X1. Y0.
N20 M30
