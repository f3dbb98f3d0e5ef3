MODULE WAAM
  ! curvedslicer: 23 points, 4 paths; eax_a = positioner tilt, eax_b = rotation (deg)
  ! positions: TCP in the positioner table frame (mechanical unit STN1)
  PERS tooldata tWaam1 := [TRUE,[[0.000,0.000,400.000],[1.00000000,0.00000000,0.00000000,0.00000000]],[2.000,[0.000,0.000,150.000],[1,0,0,0],0,0,0]];
  TASK PERS wobjdata wobjTable := [FALSE, FALSE, "STN1", [[0,0,0],[1,0,0,0]], [[0,0,0],[1,0,0,0]]];
  PROC main()
    ConfJ \On;
    ConfL \Off;
    ActUnit STN1;
    pWAAM1;
    pWAAM2;
    pWAAM3;
    pWAAM4;
    pWAAM5;
    DeactUnit STN1;
  ENDPROC
ENDMODULE
