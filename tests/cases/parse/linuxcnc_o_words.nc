(the o-words as the parser builds them)
o100 call [1] [(2 + 3)]
o<probe> call
M2
o<probe>
    o1 repeat [2] {
        G0 X<#1>
    }
    return [#1]
    endsub
