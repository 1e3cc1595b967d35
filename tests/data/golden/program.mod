MODULE ctc01_plan
  ! scanplan robot program ctc01_plan
  ! from plan.json
  ! robot abb-irb2400-10, 3 views in sequence order, rotary table as external axis 1
  ! left out, the cell cannot reach them: views 9
  ! joints in degrees as the controller counts them; the tool is the scanner frame on its mount
  ! scanner poses in the part's frame, which turns with the table, mm
  ! scan handshake: view number to output 9, trigger output 3, acknowledge input 4
  PERS tooldata tScanner := [TRUE,[[0.000,0.000,150.000],[1.000000,0.000000,0.000000,0.000000]],[3.200,[0.000,0.000,90.000],[1,0,0,0],0.02100,0.03400,0.01700]];
  ! wPart moves with the table, mechanical unit STN_1: the part in the table's frame
  ! (origin on its axis, z along it, x along the world's x at angle 0)
  PERS wobjdata wPart := [FALSE,FALSE,"STN_1",[[0,0,0],[1,0,0,0]],[[0.000,0.000,0.000],[0.965926,0.000000,0.000000,0.258819]]];
  CONST jointtarget jView4 := [[5.7296,11.4592,-17.1887,22.9183,28.6479,34.3775],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jApproach4 := [[5.7296,5.7296,-11.4592,22.9183,28.6479,34.3775],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pView4 := [[239.907,49.467,1432.983],[0.523934,0.480878,0.666812,0.222738],[0,0,0,0],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jView2 := [[-11.4592,22.9183,5.7296,-57.2958,45.8366,114.5916],[90.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pView2 := [[-402.039,59.243,862.428],[0.060587,0.884133,-0.235349,-0.399060],[-1,-1,1,0],[90.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jView7 := [[28.6479,-5.7296,17.1887,11.4592,-34.3775,-85.9437],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pView7 := [[145.383,449.759,1387.713],[0.626002,-0.301545,0.468911,-0.545266],[0,0,-1,1],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR bool bTimeout;

  PROC main()
    SetDO DO_3, 0;
    ! home
    MoveAbsJ [[0.0000,-17.1887,11.4592,0.0000,34.3775,0.0000],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]], v500, z10, tScanner;
    ! approach view 4
    MoveAbsJ jApproach4, v500, z10, tScanner;
    MoveAbsJ jView4, v100, fine, tScanner;
    Scan 4;
    ! retract view 4
    MoveAbsJ jApproach4, v100, z10, tScanner;
    ! via view 2
    MoveAbsJ [[-5.7296,-11.4592,5.7296,-28.6479,40.1070,57.2958],[45.8366,9E+09,9E+09,9E+09,9E+09,9E+09]], v500, z10, tScanner;
    MoveAbsJ jView2, v500, fine, tScanner;
    Scan 2;
    MoveAbsJ jView7, v500, fine, tScanner;
    Scan 7;
    ! home
    MoveAbsJ [[0.0000,-17.1887,11.4592,0.0000,34.3775,0.0000],[0.0000,9E+09,9E+09,9E+09,9E+09,9E+09]], v500, z10, tScanner;
  ENDPROC

  PROC Scan(num view)
    WaitTime 0.2;
    SetGO GO_9, view;
    SetDO DO_3, 1;
    WaitDI DI_4, 1 \MaxTime:=10 \TimeFlag:=bTimeout;
    IF bTimeout THEN
      SetDO DO_3, 0;
      ErrWrite "scanplan: no acknowledgement", "view " + NumToStr(view, 0);
      Stop;
    ENDIF
    SetDO DO_3, 0;
    WaitDI DI_4, 0 \MaxTime:=10 \TimeFlag:=bTimeout;
    IF bTimeout THEN
      SetDO DO_3, 0;
      ErrWrite "scanplan: no end of acknowledgement", "view " + NumToStr(view, 0);
      Stop;
    ENDIF
  ENDPROC
ENDMODULE
